// SPDX-License-Identifier: Apache-2.0
// The record layout the MCAP writer and reader share (https://mcap.dev/spec): the Magic, the
// record prefix, the Footer's size and the opcodes. Private to ncqual_mcap.
#pragma once

#include <cstdint>
#include <string_view>

namespace ncqual::mcap {

inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};
// opcode (1) + content length (8)
inline constexpr std::uint64_t kRecordPrefix = 9;
// The Footer record: prefix + summary_start (8) + summary_offset_start (8) + summary_crc (4).
inline constexpr std::uint64_t kFooterContent = 20;
inline constexpr std::uint64_t kFooterRecord = kRecordPrefix + kFooterContent;

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

}  // namespace ncqual::mcap
