// SPDX-License-Identifier: Apache-2.0
// The GUID bits DDS Security derives from a certificate's subject (ncqual/dds/identity.hpp),
// worked by hand; SecurePlant checks the same against the GUIDs Fast DDS made for each identity.
#include "ncqual/dds/identity.hpp"
#include "ncqual/dds/participant.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace ncqual::dds {
namespace {

TEST(GuidSubjectBits, AreTheTopBitThenTheSubjectHashShiftedRightByOne) {
  // a1 b2 c3 d4 e5 f6 = 1010 0001 1011 0010 1100 0011 1101 0100 1110 0101 1111 0110; with a 1
  // in front and the last bit dropped: 1101 0000 1101 1001 0110 0001 1110 1010 0111 0010 1111
  // 1011 = d0 d9 61 ea 72 fb.
  std::vector<std::uint8_t> hash(32, 0);
  const std::vector<std::uint8_t> head{0xa1, 0xb2, 0xc3, 0xd4, 0xe5, 0xf6};
  std::copy(head.begin(), head.end(), hash.begin());
  EXPECT_EQ(guid_bits_of_subject_hash(hash), (GuidSubjectBits{0xd0, 0xd9, 0x61, 0xea, 0x72, 0xfb}));
  // The top bit is set whatever the hash: eProsima's own GUIDs (01.0f...) never match one.
  EXPECT_EQ(guid_bits_of_subject_hash(std::vector<std::uint8_t>(32, 0))[0], 0x80);
  EXPECT_THROW(guid_bits_of_subject_hash({1, 2, 3}), std::invalid_argument);
}

TEST(GuidSubjectBits, AreReadFromTheGuidAsTheHistorianStoresIt) {
  EXPECT_EQ(guid_subject_bits("a5.63.3b.ec.d4.04.66.67.64.02.6c.52|0.0.3.2"),
            (GuidSubjectBits{0xa5, 0x63, 0x3b, 0xec, 0xd4, 0x04}));
  EXPECT_FALSE(guid_subject_bits(""));
  EXPECT_FALSE(guid_subject_bits("a5.63.3b"));
  EXPECT_FALSE(guid_subject_bits("zz.63.3b.ec.d4.04.66.67.64.02.6c.52|0.0.3.2"));
  EXPECT_FALSE(guid_subject_bits("a5-63-3b-ec-d4-04-66-67-64-02-6c-52"));
}

TEST(PlantIdentities, AGuidNamesTheIdentityWhoseBitsItCarriesAndNoneElse) {
  const std::vector<PlantIdentity> ids{
      {"scheduler", "CN=scheduler", {0xd0, 0xd9, 0x61, 0xea, 0x72, 0xfb}},
      {"solver", "CN=solver", {0xa5, 0x63, 0x3b, 0xec, 0xd4, 0x04}}};
  const auto solver = identity_of_guid("a5.63.3b.ec.d4.04.27.04.8d.7a.f8.c2|0.0.3.2", ids);
  ASSERT_TRUE(solver);
  EXPECT_EQ(solver->name, "solver");
  EXPECT_FALSE(identity_of_guid("01.0f.78.fd.5b.6f.cf.f4.01.00.00.00|0.0.3.2", ids));
  EXPECT_FALSE(identity_of_guid("a5.63.3b.ec.d4.05.27.04.8d.7a.f8.c2|0.0.3.2", ids));
  EXPECT_THROW(plant_identities("/nonexistent-ncqual-pki"), std::runtime_error);
}

TEST(PlantIdentities, ARefusedRemoteEndpointIsSaidWithItsIdentityAndWhy) {
  const std::vector<PlantIdentity> ids{{"acquisition-pm1",
                                        "CN=acquisition-pm1,OU=acquisition,O=plant F",
                                        {0xa5, 0x63, 0x3b, 0xec, 0xd4, 0x04}}};
  // As Fast DDS 2.9.1's SecurityManager::discovered_writer logs it.
  const auto said = describe_refused_endpoint(
      "Error checking create remote writer a5.63.3b.ec.d4.04.27.04.8d.7a.f8.c2|0.0.5.3 (<empty> "
      "partition not found in rule.)",
      ids);
  ASSERT_TRUE(said);
  EXPECT_EQ(*said,
            "DDS Security refused a remote writer of identity 'acquisition-pm1' "
            "(CN=acquisition-pm1,OU=acquisition,O=plant F; writer "
            "a5.63.3b.ec.d4.04.27.04.8d.7a.f8.c2|0.0.5.3): <empty> partition not found in rule.; "
            "nothing it writes is received");
  const auto stranger = describe_refused_endpoint(
      "Error checking create remote reader 80.01.02.03.04.05.27.04.8d.7a.f8.c2|0.0.6.4 "
      "(ncqual/machine/pm2 partition not found in rule.)",
      ids);
  ASSERT_TRUE(stranger);
  EXPECT_NE(stranger->find("remote reader of (no identity of the plant; reader "
                           "80.01.02.03.04.05.27.04.8d.7a.f8.c2|0.0.6.4)"),
            std::string::npos)
      << *stranger;
  EXPECT_NE(stranger->find("ncqual/machine/pm2 partition not found"), std::string::npos);
  EXPECT_FALSE(describe_refused_endpoint("Participant discovered", ids));
}

}  // namespace
}  // namespace ncqual::dds

namespace ncqual::dds {
namespace {

NetworkAddress address(std::string host) {
  NetworkAddress a;
  a.host = std::move(host);
  return a;
}

// Where a participant's unicast transports listen: this host's addresses among the plant's, in
// the plant's order, each once (a host name counts as the address it resolves to); nothing, so
// every interface, when the plant names none of them.
TEST(ListeningAddresses, AreThisHostsAddressesAmongThePlantsPeersAndServers) {
  NetworkConfig network;
  network.discovery = Discovery::Peers;
  network.peers = {address("10.1.0.10"), address("10.1.0.21"), address("127.0.0.1"),
                   address("localhost")};
  EXPECT_EQ(listening_addresses(network, {"127.0.0.1", "10.1.0.21", "192.168.7.3"}),
            (std::vector<std::string>{"10.1.0.21", "127.0.0.1"}));
  EXPECT_TRUE(listening_addresses(network, {"192.168.7.3"}).empty());
  network.peers.clear();
  network.servers = {address("10.1.0.5")};
  EXPECT_EQ(listening_addresses(network, {"10.1.0.5", "127.0.0.1"}),
            (std::vector<std::string>{"10.1.0.5"}));
  EXPECT_TRUE(listening_addresses(NetworkConfig{}, {"127.0.0.1"}).empty());
}

}  // namespace
}  // namespace ncqual::dds
