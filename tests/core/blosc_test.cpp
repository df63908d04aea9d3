// Tests for the Blosc1 / LZ4 decompression an OpenVDB file's Blosc grids need: LZ4 sequences with
// length extensions and overlapping matches, a shuffled chunk split per byte (one split raw, one LZ4),
// a raw chunk, and corrupt input refused rather than read past.
#include "base/blosc.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace ppm;

std::vector<uint8_t> lz4(const std::vector<uint8_t>& block, size_t out_size) {
  std::vector<uint8_t> out(out_size);
  lz4_decompress_block(block.data(), block.size(), out.data(), out.size());
  return out;
}

TEST(Lz4, CopiesLiteralsAndOverlappingMatches) {
  // "abc", then 9 bytes from 3 back (overlapping itself), then the last literals "defgh".
  const std::vector<uint8_t> block = {0x35, 'a', 'b', 'c', 3, 0, 0x50, 'd', 'e', 'f', 'g', 'h'};
  const std::vector<uint8_t> out = lz4(block, 17);
  EXPECT_EQ(std::string(out.begin(), out.end()), "abcabcabcabcdefgh");
}

TEST(Lz4, ReadsLengthExtensions) {
  // 20 literals (15 + 5), a run of 506 copies of the last from 1 back (15 + 255 + 232 + 4), then 5 zeros.
  std::vector<uint8_t> block = {0xFF, 5};
  for (int i = 0; i < 20; ++i) block.push_back(uint8_t('A' + i));
  const std::vector<uint8_t> run = {1, 0, 255, 232, 0x50, 0, 0, 0, 0, 0};
  block.insert(block.end(), run.begin(), run.end());
  const std::vector<uint8_t> out = lz4(block, 20 + 506 + 5);
  EXPECT_EQ(out[0], 'A');
  for (size_t i = 19; i < 20 + 506; ++i) ASSERT_EQ(out[i], 'T') << i;
  for (size_t i = 20 + 506; i < out.size(); ++i) ASSERT_EQ(out[i], 0) << i;
}

TEST(Lz4, RefusesWhatWouldReadOrWriteOutOfBounds) {
  EXPECT_THROW(lz4({0x10, 'a', 0, 0, 0x00}, 10), std::invalid_argument);      // offset 0
  EXPECT_THROW(lz4({0x10, 'a', 5, 0, 0x00}, 10), std::invalid_argument);      // before the output
  EXPECT_THROW(lz4({0x30, 'a', 'b', 'c'}, 2), std::invalid_argument);        // past the output
  EXPECT_THROW(lz4({0x50, 'a'}, 5), std::invalid_argument);                  // literals past the block
  EXPECT_THROW(lz4({0x20, 'a', 'b'}, 3), std::invalid_argument);             // short of the output
  EXPECT_THROW(lz4({0xF0}, 300), std::invalid_argument);                     // a length cut short
}

void put32(std::vector<uint8_t>& v, uint32_t x) {
  for (int k = 0; k < 4; ++k) v.push_back(uint8_t(x >> (8 * k)));
}

// 512 floats, byte-shuffled and split in four (as OpenVDB's Blosc writes a full leaf): the low
// bytes stored raw, the other three planes all zero (small integers), each one LZ4 run.
TEST(Blosc, UnshufflesAChunkSplitPerByteOfItsValues) {
  std::vector<float> values(512);
  std::vector<uint8_t> bytes(512 * 4);
  for (int i = 0; i < 512; ++i) {
    const uint32_t bits = uint32_t(i % 251);  // denormal floats whose only non-zero byte is the low one
    std::memcpy(&values[i], &bits, 4);
  }
  std::memcpy(bytes.data(), values.data(), bytes.size());
  std::vector<uint8_t> chunk = {2, 1, 0x21, 4};  // version, LZ4 format, shuffle + codec LZ4, 4-byte values
  put32(chunk, 2048), put32(chunk, 2048), put32(chunk, 0);  // nbytes, blocksize, cbytes (below)
  put32(chunk, 20);                                           // block 0 starts after its offset
  put32(chunk, 512);                                          // split 0: the low bytes, raw
  for (int i = 0; i < 512; ++i) chunk.push_back(bytes[4 * i]);
  const std::vector<uint8_t> zeros = {0x1F, 0, 1, 0, 255, 232, 0x50, 0, 0, 0, 0, 0};  // 512 zero bytes
  for (int s = 1; s < 4; ++s) {
    put32(chunk, uint32_t(zeros.size()));
    chunk.insert(chunk.end(), zeros.begin(), zeros.end());
  }
  const uint32_t size = uint32_t(chunk.size());
  std::memcpy(chunk.data() + 12, &size, 4);
  const std::vector<uint8_t> out = blosc_decompress(chunk.data(), chunk.size());
  ASSERT_EQ(out.size(), bytes.size());
  EXPECT_EQ(out, bytes);
}

TEST(Blosc, CopiesARawChunkUnshuffled) {
  std::vector<uint8_t> chunk = {2, 1, 0x33, 4};  // memcpyed: the shuffle flag does not apply
  put32(chunk, 8), put32(chunk, 8), put32(chunk, 24);
  for (uint8_t b = 1; b <= 8; ++b) chunk.push_back(b);
  const std::vector<uint8_t> out = blosc_decompress(chunk.data(), chunk.size());
  EXPECT_EQ(out, std::vector<uint8_t>({1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(Blosc, RefusesOtherCodecsAndCorruptChunks) {
  std::vector<uint8_t> zstd = {2, 1, uint8_t(4 << 5), 4};
  put32(zstd, 8), put32(zstd, 8), put32(zstd, 32);
  zstd.resize(32, 0);
  EXPECT_THROW(blosc_decompress(zstd.data(), zstd.size()), std::invalid_argument);
  std::vector<uint8_t> short_chunk = {2, 1, 0x21, 4};
  put32(short_chunk, 4096), put32(short_chunk, 4096), put32(short_chunk, 20);
  put32(short_chunk, 4000);  // the block starts past the chunk
  EXPECT_THROW(blosc_decompress(short_chunk.data(), short_chunk.size()), std::invalid_argument);
  EXPECT_THROW(blosc_decompress(short_chunk.data(), 10), std::invalid_argument);
}

}  // namespace
