// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/identity.hpp"

#include <spdlog/spdlog.h>

#include <openssl/bio.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace ncqual::dds {

GuidSubjectBits guid_bits_of_subject_hash(const std::vector<std::uint8_t>& subject_sha256) {
  if (subject_sha256.size() < 6) {
    throw std::invalid_argument("a subject hash has 32 bytes; got " +
                                std::to_string(subject_sha256.size()));
  }
  const auto& md = subject_sha256;
  // The top bit marks a GUID made so; the hash's bits follow, shifted right by one.
  GuidSubjectBits bits{};
  bits[0] = static_cast<std::uint8_t>(0x80U | (md[0] >> 1U));
  for (std::size_t i = 1; i < bits.size(); ++i) {
    bits[i] = static_cast<std::uint8_t>(((md[i - 1] << 7U) | (md[i] >> 1U)) & 0xFFU);
  }
  return bits;
}

std::optional<GuidSubjectBits> guid_subject_bits(const std::string& guid_text) {
  // "xx.xx.xx.xx.xx.xx.…": six two-digit hex bytes, each followed by a dot.
  GuidSubjectBits bits{};
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const std::size_t at = i * 3;
    if (guid_text.size() < at + 3 || guid_text[at + 2] != '.') return std::nullopt;
    const std::string hex = guid_text.substr(at, 2);
    if (!std::all_of(hex.begin(), hex.end(), [](char c) { return std::isxdigit(c) != 0; })) {
      return std::nullopt;
    }
    bits[i] = static_cast<std::uint8_t>(std::stoi(hex, nullptr, 16));
  }
  return bits;
}

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
struct X509Free {
  void operator()(X509* x) const { X509_free(x); }
};

PlantIdentity read_identity(const std::filesystem::path& cert_file, const std::string& name) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(cert_file.c_str(), "rb"));
  if (!file) throw std::runtime_error(cert_file.string() + ": cannot be opened");
  std::unique_ptr<X509, X509Free> cert(PEM_read_X509(file.get(), nullptr, nullptr, nullptr));
  if (!cert) throw std::runtime_error(cert_file.string() + ": not a PEM certificate");
  const X509_NAME* subject = X509_get_subject_name(cert.get());
  std::vector<std::uint8_t> digest(EVP_MAX_MD_SIZE);
  unsigned int length = 0;
  if (X509_NAME_digest(subject, EVP_sha256(), digest.data(), &length) != 1 || length != 32) {
    throw std::runtime_error(cert_file.string() + ": SHA-256 of its subject failed (OpenSSL)");
  }
  digest.resize(length);
  PlantIdentity identity;
  identity.name = name;
  identity.bits = guid_bits_of_subject_hash(digest);
  std::unique_ptr<BIO, decltype(&BIO_free)> text(BIO_new(BIO_s_mem()), &BIO_free);
  X509_NAME_print_ex(text.get(), subject, 0, XN_FLAG_RFC2253);
  char* data = nullptr;
  const long size = BIO_get_mem_data(text.get(), &data);
  identity.subject.assign(data, static_cast<std::size_t>(size));
  return identity;
}

}  // namespace

std::vector<PlantIdentity> plant_identities(const std::string& dir) {
  std::vector<PlantIdentity> out;
  const std::filesystem::path identities = std::filesystem::path(dir) / "identities";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(identities, ec)) {
    const auto cert = entry.path() / "cert.pem";
    if (!entry.is_directory() || !std::filesystem::exists(cert)) continue;
    out.push_back(read_identity(cert, entry.path().filename().string()));
  }
  if (ec) throw std::runtime_error(identities.string() + ": " + ec.message());
  std::sort(out.begin(), out.end(),
            [](const PlantIdentity& a, const PlantIdentity& b) { return a.name < b.name; });
  return out;
}

std::optional<PlantIdentity> identity_of_guid(const std::string& guid_text,
                                              const std::vector<PlantIdentity>& identities) {
  const auto bits = guid_subject_bits(guid_text);
  if (!bits) return std::nullopt;
  for (const auto& identity : identities) {
    if (identity.bits == *bits) return identity;
  }
  return std::nullopt;
}

std::vector<PlantIdentity> plant_identities_to_name(const std::string& dir, const char* what) {
  if (dir.empty()) return {};
  try {
    return plant_identities(dir);
  } catch (const std::exception& e) {
    spdlog::warn("the plant's identities are not read ({}): {} name writers by GUID", e.what(),
                 what);
    return {};
  }
}

std::string writer_name(const std::string& guid_text,
                        const std::vector<PlantIdentity>& identities) {
  const auto id = identity_of_guid(guid_text, identities);
  return id ? id->name + " (writer " + guid_text + ")" : "writer " + guid_text;
}

std::optional<std::string> describe_refused_endpoint(const std::string& fast_dds_message,
                                                     const std::vector<PlantIdentity>& identities) {
  static const std::string kPrefix = "Error checking create remote ";
  const std::size_t at = fast_dds_message.find(kPrefix);
  if (at == std::string::npos) return std::nullopt;
  std::size_t pos = at + kPrefix.size();
  const std::size_t kind_end = fast_dds_message.find(' ', pos);
  if (kind_end == std::string::npos) return std::nullopt;
  const std::string kind = fast_dds_message.substr(pos, kind_end - pos);  // writer, reader
  pos = kind_end + 1;
  const std::size_t guid_end = fast_dds_message.find(' ', pos);
  const std::string guid = fast_dds_message.substr(
      pos, guid_end == std::string::npos ? std::string::npos : guid_end - pos);
  std::string why;
  if (guid_end != std::string::npos) {
    why = fast_dds_message.substr(guid_end + 1);
    if (why.size() >= 2 && why.front() == '(') why = why.substr(1, why.rfind(')') - 1);
  }
  const auto identity = identity_of_guid(guid, identities);
  const std::string who = identity ? "identity '" + identity->name + "' (" + identity->subject +
                                         "; " + kind + " " + guid + ")"
                                   : "(no identity of the plant; " + kind + " " + guid + ")";
  return "DDS Security refused a remote " + kind + " of " + who + ": " +
         (why.empty() ? "its permissions do not allow it" : why) +
         (kind == "writer" ? "; nothing it writes is received" : "; it receives nothing");
}

}  // namespace ncqual::dds
