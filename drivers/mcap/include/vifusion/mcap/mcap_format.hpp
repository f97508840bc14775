#pragma once
// The fixed parts of the MCAP container, version 0 (https://mcap.dev/spec): magic, record opcodes and the
// byte sizes of the fixed-width record fields that the writer and the reader both lay out. All integers
// are little-endian; a record is <opcode u8><content length u64><content>.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace vifusion::mcap {

/// The 8 bytes that open and close every MCAP file: 0x89 "MCAP" '0' (major version) "\r\n".
inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

/// Record opcodes of the specification; 0x10..0x7F are reserved, 0x80..0xFF private (readers skip both).
enum class Opcode : std::uint8_t {
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

/// Opcodes from here on are not defined by version 0 of the specification: reserved up to 0x7F, private
/// from 0x80. Readers skip such records.
inline constexpr std::uint8_t kFirstUndefinedOpcode = 0x10;

/// The record's name as the specification writes it ("Chunk", "Message Index"); for opcodes it does not
/// define, "private record" (0x80..0xFF) or "reserved record".
std::string_view opcodeName(std::uint8_t opcode);

/// <opcode u8><content length u64>.
inline constexpr std::size_t kRecordHeaderBytes = 1 + 8;
/// Where a record's content length sits: right after its opcode byte.
inline constexpr std::size_t kRecordLengthAt = 1;
/// Message content before its data: channel_id u16, sequence u32, log_time u64, publish_time u64.
inline constexpr std::size_t kMessageFieldsBytes = 2 + 4 + 8 + 8;
/// A whole Message record before its data.
inline constexpr std::size_t kMessageRecordPrefixBytes = kRecordHeaderBytes + kMessageFieldsBytes;
/// Chunk content before its records, with an empty compression string: message_start_time u64,
/// message_end_time u64, uncompressed_size u64, uncompressed_crc u32, compression (u32 length + 0
/// bytes), records length u64.
inline constexpr std::size_t kChunkFieldsBytes = 8 + 8 + 8 + 4 + 4 + 8;
/// A whole uncompressed Chunk record before its records.
inline constexpr std::size_t kChunkRecordPrefixBytes = kRecordHeaderBytes + kChunkFieldsBytes;
/// One Message Index entry: log_time u64, offset u64 (from the start of the chunk's records).
inline constexpr std::size_t kMessageIndexEntryBytes = 8 + 8;
/// Message Index content before its entries: channel_id u16, entries byte length u32.
inline constexpr std::size_t kMessageIndexFieldsBytes = 2 + 4;
/// DataEnd content: data_section_crc u32.
inline constexpr std::size_t kDataEndFieldsBytes = 4;
/// Footer content: summary_start u64, summary_offset_start u64, summary_crc u32.
inline constexpr std::size_t kFooterFieldsBytes = 8 + 8 + 4;
/// Footer record and closing magic: what a reader looks for at the end of a complete file.
inline constexpr std::size_t kFooterAndMagicBytes = kRecordHeaderBytes + kFooterFieldsBytes + kMagic.size();

/// Profile of ROS 2 recordings (messages in CDR, schemas in ros2msg or ros2idl): what `ros2 bag` writes.
inline constexpr std::string_view kProfileRos2 = "ros2";
/// Uncompressed chunks: the only compression this writer produces and this reader accepts.
inline constexpr std::string_view kCompressionNone = "";

}  // namespace vifusion::mcap
