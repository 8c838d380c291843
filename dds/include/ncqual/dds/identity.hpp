// SPDX-License-Identifier: Apache-2.0
// Which of the plant's identities a DataWriter belongs to, from its GUID alone.
//
// DDS Security's PKI-DH authentication makes a secured participant's GUID from its certificate:
// the first six bytes of the GUID prefix are 0x80 followed by the first 47 bits of the SHA-256
// of the certificate's subject name (DER). The handshake checks these bits against the
// certificate the peer proved it holds (Fast DDS 2.9.1's PKIDH.cpp: adjust_participant_key makes
// them; begin_handshake_reply and process_handshake_request refuse a peer whose bits differ), so on
// a secured plant the GUID the historian records with every sample names the identity that wrote
// it, for as long as the record is kept. Two certificates of one subject (a re-issued one, or
// another CA's of the same name) give the same bits; only the plant CA's are authenticated, so only
// they can be behind a stored sample.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::dds {

using GuidSubjectBits = std::array<std::uint8_t, 6>;

// The first six GUID prefix bytes of a participant whose certificate subject hashes (SHA-256 of
// its DER encoding) to `subject_sha256` (32 bytes; fewer than 6 is an error).
GuidSubjectBits guid_bits_of_subject_hash(const std::vector<std::uint8_t>& subject_sha256);

// The first six bytes of a GUID as the historian stores it ("a5.63.3b.ec.d4.04.…|0.0.3.2");
// nullopt when the text is not a GUID.
std::optional<GuidSubjectBits> guid_subject_bits(const std::string& guid_text);

struct PlantIdentity {
  std::string name;     // the directory's name: "solver", "acquisition-good", "operator-station1"
  std::string subject;  // RFC 2253, e.g. "CN=solver,OU=ncqual,O=plant F"
  GuidSubjectBits bits{};
};

// The identities of ncqual-pki's `dir` (identities/<name>/cert.pem; keys are not read), sorted
// by name. Throws std::runtime_error naming the file when a certificate cannot be read.
std::vector<PlantIdentity> plant_identities(const std::string& dir);

// The identity whose subject bits the GUID carries, if any. An open plant's GUIDs (eProsima's
// 01.0f prefix) never match: their first bit is 0.
std::optional<PlantIdentity> identity_of_guid(const std::string& guid_text,
                                              const std::vector<PlantIdentity>& identities);

// As plant_identities, for naming writers in messages: none when `dir` is "" (an open plant) or
// cannot be read (warned, saying that `what` then names them by GUID).
std::vector<PlantIdentity> plant_identities_to_name(const std::string& dir, const char* what);

// A writer's GUID as a conflict names it: "solver (writer GUID)" when the GUID carries a plant
// identity's subject bits, else "writer GUID".
std::string writer_name(const std::string& guid_text, const std::vector<PlantIdentity>& identities);

// What Fast DDS 2.9.1 logs when DDS Security refuses a remote endpoint (SecurityManager:
// "Error checking create remote writer <GUID> (<why>)", the same for a reader), said for people:
// "refused a remote writer of identity 'acquisition-pm1' (CN=...; writer <GUID>): <why>; nothing
// it writes is received". nullopt for any other message. The identity is the plant's whose
// subject bits the GUID carries, else "(no identity of the plant)".
std::optional<std::string> describe_refused_endpoint(const std::string& fast_dds_message,
                                                     const std::vector<PlantIdentity>& identities);

}  // namespace ncqual::dds
