// Decompression of a Blosc1 chunk (c-blosc's format) whose codec is LZ4, as OpenVDB writes the
// values of a grid saved with Blosc (docs: the chunk's 16-byte header, its block offsets, splits per
// byte of a value, byte shuffle). Written here rather than linked: the core must not bring a
// library Blender also loads (c-blosc comes with Blender's OpenVDB).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppm {

// The chunk's `size` bytes decompressed; throws std::invalid_argument for a chunk that is not a
// Blosc1 chunk of LZ4 or raw blocks (another codec, bit-shuffle, or corrupt data).
std::vector<uint8_t> blosc_decompress(const uint8_t* chunk, size_t size);

// One LZ4 block (its `size` bytes) into exactly `out_size` bytes at `out`; throws
// std::invalid_argument if the block is corrupt or does not fill them exactly.
void lz4_decompress_block(const uint8_t* in, size_t size, uint8_t* out, size_t out_size);

}  // namespace ppm
