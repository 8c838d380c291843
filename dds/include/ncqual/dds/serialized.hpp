// SPDX-License-Identifier: Apache-2.0
// A sample as bytes: its CDR serialization as Fast DDS 2.9 puts it on the wire (encapsulation
// header included), and the SHA-256 of those bytes, which names the sample's content in
// acknowledgements, outboxes and the historian. The buffer is zeroed before serializing, so the
// alignment padding is zero and equal values give equal bytes (and equal hashes) in every process.
#pragma once

#include <fastdds/rtps/common/SerializedPayload.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ncqual::dds {

// Lower-case hex SHA-256 of `size` bytes (OpenSSL).
std::string sha256_hex(const std::uint8_t* data, std::size_t size);
inline std::string sha256_hex(const std::vector<std::uint8_t>& bytes) {
  return sha256_hex(bytes.data(), bytes.size());
}

// The CDR bytes of a wire sample of `Topic`.
template <typename Topic>
std::vector<std::uint8_t> serialize(const typename Topic::Wire& wire) {
  typename Topic::PubSub type;
  auto& data = const_cast<typename Topic::Wire&>(wire);  // the generated API takes void*
  const std::uint32_t size = type.getSerializedSizeProvider(&data)();
  eprosima::fastrtps::rtps::SerializedPayload_t payload(size);
  if (!type.serialize(&data, &payload)) return {};
  return std::vector<std::uint8_t>(payload.data, payload.data + payload.length);
}

// Reads CDR bytes back into a wire sample; false when they are not a sample of `Topic`.
template <typename Topic>
bool deserialize(const std::vector<std::uint8_t>& bytes, typename Topic::Wire& wire) {
  typename Topic::PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::copy(bytes.begin(), bytes.end(), payload.data);
  payload.length = static_cast<std::uint32_t>(bytes.size());
  try {
    return type.deserialize(&payload, &wire);
  } catch (const std::exception&) {
    return false;  // Fast CDR throws NotEnoughMemoryException on a truncated buffer
  }
}

}  // namespace ncqual::dds
