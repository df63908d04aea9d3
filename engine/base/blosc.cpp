// Blosc1 chunks of LZ4 blocks (see blosc.h): the header, blocks, splits and byte unshuffle of
// c-blosc 1.x, and the LZ4 block format (token, literals, 2-byte offset, match of at least 4).
#include "base/blosc.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace ppm {

namespace {

[[noreturn]] void corrupt(const std::string& why) { throw std::invalid_argument("blosc chunk: " + why); }

uint32_t le32(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }

// LZ4's length: a nibble, and while it is 15, bytes added until one is below 255.
size_t lz4_length(size_t nibble, const uint8_t*& p, const uint8_t* end) {
  size_t n = nibble;
  if (nibble != 15) return n;
  for (;;) {
    if (p >= end) corrupt("an LZ4 length runs past the block");
    const uint8_t b = *p++;
    n += b;
    if (b != 255) return n;
  }
}

constexpr uint8_t kShuffle = 0x01, kMemcpyed = 0x02, kBitShuffle = 0x04, kReserved = 0x08, kDontSplit = 0x10;
constexpr int kLz4Codec = 1;
constexpr size_t kHeader = 16, kMinSplitValues = 128, kMaxSplits = 16;

// Block `bsize` bytes from its compressed splits at chunk offset `start` into `out`.
void decompress_block(const uint8_t* chunk, size_t size, size_t start, size_t bsize, size_t typesize, bool split,
                      uint8_t* out) {
  const size_t splits = split ? typesize : 1, each = bsize / splits;
  size_t at = start;
  for (size_t s = 0; s < splits; ++s) {
    if (at + 4 > size) corrupt("a split's size lies past the chunk");
    const size_t csize = le32(chunk + at);
    at += 4;
    if (csize > size - at) corrupt("a split lies past the chunk");
    if (csize == each)
      std::memcpy(out + s * each, chunk + at, each);  // stored raw: the codec could not shrink it
    else
      lz4_decompress_block(chunk + at, csize, out + s * each, each);
    at += csize;
  }
}

void unshuffle(const uint8_t* in, size_t bsize, size_t typesize, uint8_t* out) {
  const size_t q = bsize / typesize;
  for (size_t i = 0; i < q; ++i)
    for (size_t b = 0; b < typesize; ++b) out[i * typesize + b] = in[b * q + i];
  std::memcpy(out + q * typesize, in + q * typesize, bsize - q * typesize);
}

}  // namespace

void lz4_decompress_block(const uint8_t* in, size_t size, uint8_t* out, size_t out_size) {
  const uint8_t *p = in, *end = in + size;
  size_t o = 0;
  while (p < end) {
    const uint8_t token = *p++;
    const size_t literals = lz4_length(token >> 4, p, end);
    if (literals > size_t(end - p) || literals > out_size - o) corrupt("LZ4 literals run past the block");
    std::memcpy(out + o, p, literals);
    p += literals, o += literals;
    if (p == end) break;  // the last sequence: literals only
    if (end - p < 2) corrupt("an LZ4 offset is cut short");
    const size_t offset = size_t(p[0]) | size_t(p[1]) << 8;
    p += 2;
    if (offset == 0 || offset > o) corrupt("an LZ4 match reaches before the output");
    const size_t match = lz4_length(token & 15, p, end) + 4;
    if (match > out_size - o) corrupt("an LZ4 match runs past the output");
    for (size_t k = 0; k < match; ++k, ++o) out[o] = out[o - offset];  // (may overlap itself)
  }
  if (o != out_size) corrupt("an LZ4 block decompressed to " + std::to_string(o) + " bytes, not " +
                             std::to_string(out_size));
}

std::vector<uint8_t> blosc_decompress(const uint8_t* chunk, size_t size) {
  if (size < kHeader) corrupt("shorter than its header");
  const uint8_t flags = chunk[2];
  const size_t typesize = chunk[3], nbytes = le32(chunk + 4), blocksize = le32(chunk + 8), cbytes = le32(chunk + 12);
  if (chunk[0] != 2) corrupt("format version " + std::to_string(chunk[0]) + ", not 2");
  if (flags & kReserved) corrupt("a reserved flag is set");
  if (cbytes > size) corrupt("its size says more bytes than it has");
  std::vector<uint8_t> out(nbytes);
  if (nbytes == 0) return out;
  if (flags & kMemcpyed) {  // raw, never shuffled
    if (cbytes < kHeader + nbytes) corrupt("a raw chunk shorter than its data");
    std::memcpy(out.data(), chunk + kHeader, nbytes);
    return out;
  }
  if ((flags >> 5) != kLz4Codec) corrupt("codec " + std::to_string(flags >> 5) + " (only LZ4 is read)");
  if (flags & kBitShuffle) corrupt("bit-shuffled (only byte shuffle is read)");
  if (blocksize == 0 || typesize == 0) corrupt("an empty block or value size");
  const size_t blocks = nbytes / blocksize + (nbytes % blocksize ? 1 : 0);
  if (kHeader + 4 * blocks > cbytes) corrupt("its block offsets lie past it");
  std::vector<uint8_t> block(blocksize);
  for (size_t j = 0; j < blocks; ++j) {
    const bool leftover = j + 1 == blocks && nbytes % blocksize != 0;
    const size_t bsize = leftover ? nbytes % blocksize : blocksize, start = le32(chunk + kHeader + 4 * j);
    const bool split =
        !(flags & kDontSplit) && typesize <= kMaxSplits && bsize / typesize >= kMinSplitValues && !leftover;
    if (split && bsize % typesize != 0) corrupt("a split block is not a whole number of values");
    uint8_t* dest = out.data() + j * blocksize;
    const bool shuffled = (flags & kShuffle) && typesize > 1;
    decompress_block(chunk, cbytes, start, bsize, typesize, split, shuffled ? block.data() : dest);
    if (shuffled) unshuffle(block.data(), bsize, typesize, dest);
  }
  return out;
}

}  // namespace ppm
