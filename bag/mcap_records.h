#pragma once
// Parsers of single MCAP record contents, shared by the linear reader and the summary reader.
// Each returns nullopt when the content is shorter than its fields (a corrupt record).
#include <optional>

#include "bag/mcap_bytes.h"
#include "bag/mcap_reader.h"

namespace cairn::bag {

std::optional<McapSchema> parse_schema(const uint8_t* data, size_t size);
std::optional<McapChannel> parse_channel(const uint8_t* data, size_t size);
std::optional<McapMessage> parse_message(const uint8_t* data, size_t size);
std::optional<McapChunkIndex> parse_chunk_index(const uint8_t* data, size_t size);
/// Fills the statistics fields of `summary`.
bool parse_statistics(const uint8_t* data, size_t size, McapSummary* summary);
/// A Map<uint16, uint64> field.
std::optional<std::map<uint16_t, uint64_t>> parse_id_map(ByteReader& r);

}  // namespace cairn::bag
