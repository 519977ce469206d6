#include "patchextract/hdf5_damage_check.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string_view>
#include <vector>

namespace mdbrief::train {

namespace {

constexpr std::string_view kHeapSignature = "HEAP";

class RandomReader {
 public:
  explicit RandomReader(const std::filesystem::path& path) : in_(path, std::ios::binary) {
    in_.seekg(0, std::ios::end);
    size_ = in_ ? static_cast<uint64_t>(in_.tellg()) : 0;
  }
  bool ok() const { return static_cast<bool>(in_); }
  uint64_t size() const { return size_; }
  // Reads bytes [offset, offset + n) into out; false if they are not all inside the file.
  bool read(uint64_t offset, size_t n, uint8_t* out) {
    if (offset > size_ || n > size_ - offset) return false;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
    return static_cast<size_t>(in_.gcount()) == n;
  }

 private:
  std::ifstream in_;
  uint64_t size_ = 0;
};

// A little-endian unsigned number of `bytes` bytes (HDF5 stores every address and length so).
uint64_t decode(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

uint64_t undefined(int bytes) { return bytes >= 8 ? ~uint64_t(0) : (uint64_t(1) << (8 * bytes)) - 1; }

struct Sizes {
  int offsets = 0, lengths = 0;
  uint64_t baseAddress = 0;
};

// The superblock is at byte 0, 512, 1024, 2048, ... (a user block may precede it).
std::string readSuperblock(RandomReader& in, Sizes& s) {
  static constexpr uint8_t kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  uint8_t b[16] = {};
  uint64_t at = 0;
  while (!(in.read(at, sizeof b, b) && std::equal(kSignature, kSignature + 8, b))) {
    at = at == 0 ? 512 : 2 * at;
    if (at >= in.size()) return "no HDF5 superblock";
  }
  const int version = b[8];
  // The field positions of each superblock version, from the specification's layouts.
  uint64_t baseAt = 0;
  if (version == 0 || version == 1) {
    s.offsets = b[13];
    s.lengths = b[14];
    baseAt = version == 0 ? 24 : 28;
  } else if (version == 2 || version == 3) {
    s.offsets = b[9];
    s.lengths = b[10];
    baseAt = 12;
  } else {
    return "unknown HDF5 superblock version " + std::to_string(version);
  }
  const auto supported = [](int n) { return n == 2 || n == 4 || n == 8; };
  if (!supported(s.offsets) || !supported(s.lengths))
    return "HDF5 superblock declares " + std::to_string(s.offsets) + "-byte offsets and " +
           std::to_string(s.lengths) + "-byte lengths";
  if (!in.read(at + baseAt, static_cast<size_t>(s.offsets), b)) return "HDF5 superblock is cut short";
  s.baseAddress = decode(b, s.offsets);
  return "";
}

// The local heap whose header may be at `at`: its free list must end. Anything else libhdf5
// refuses by itself, and a signature inside pixel data (no version 0, reserved bytes not zero,
// or a list that ends) is left alone.
std::string localHeapProblem(RandomReader& in, const Sizes& s, uint64_t at) {
  // Header: signature, version 0, 3 reserved bytes, data segment size (length), offset of the
  // first free block (length), data segment address (offset).
  std::vector<uint8_t> h(8 + 2 * s.lengths + s.offsets);
  if (!in.read(at, h.size(), h.data()) || h[4] != 0 || h[5] != 0 || h[6] != 0 || h[7] != 0) return "";
  const uint64_t segmentSize = decode(&h[8], s.lengths);
  uint64_t block = decode(&h[8 + s.lengths], s.lengths);
  const uint64_t address = decode(&h[8 + 2 * s.lengths], s.offsets);
  if (address > in.size() || s.baseAddress > in.size() - address ||
      segmentSize > in.size() - s.baseAddress - address)
    return "";
  std::vector<uint8_t> segment(static_cast<size_t>(segmentSize));
  if (!in.read(s.baseAddress + address, segment.size(), segment.data())) return "";
  // Each free block starts with the offset of the next and its own size. Damaged blocks may
  // overlap, so only a walk longer than the number of places a block can start must loop.
  const uint64_t entry = 2 * static_cast<uint64_t>(s.lengths);
  const uint64_t maxBlocks = segmentSize < entry ? 0 : segmentSize - entry + 1;
  for (uint64_t visited = 0; block != undefined(s.lengths); ++visited) {
    if (block > segmentSize || entry > segmentSize - block) return "";
    if (visited >= maxBlocks)
      return "the local heap at byte " + std::to_string(at) + " has a free list that loops";
    block = decode(&segment[block], s.lengths);
  }
  return "";
}

}  // namespace

std::string hdf5DamageProblem(const std::filesystem::path& path) {
  RandomReader in(path);
  if (!in.ok()) return "cannot be read";
  Sizes sizes;
  if (std::string problem = readSuperblock(in, sizes); !problem.empty()) return problem;
  // libhdf5 loads a local heap only where its signature is, so every one it could follow is
  // found by scanning the whole file for the signature.
  constexpr size_t kChunk = size_t(1) << 20;
  const size_t overlap = kHeapSignature.size() - 1;
  std::vector<uint8_t> chunk(kChunk + overlap);
  for (uint64_t start = 0; start < in.size(); start += kChunk) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(chunk.size(), in.size() - start));
    if (!in.read(start, n, chunk.data())) return "cannot be read";
    const std::string_view view(reinterpret_cast<const char*>(chunk.data()), n);
    for (size_t i = view.find(kHeapSignature); i != std::string_view::npos && i < kChunk;
         i = view.find(kHeapSignature, i + 1))
      if (std::string problem = localHeapProblem(in, sizes, start + i); !problem.empty()) return problem;
  }
  return "";
}

}  // namespace mdbrief::train
