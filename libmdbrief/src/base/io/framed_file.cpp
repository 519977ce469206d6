#include "mdbrief/internal/base/io/framed_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"

// The files are little-endian and read in place; a big-endian port would swap on load.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the framed files are read in place as little-endian");

namespace mdbrief::internal {

namespace {

// Under AddressSanitizer the file is read, not mapped: ASan reports a read past the end of a
// heap buffer, but the rest of a mapping's last page reads as zeros unnoticed, and the readers
// behind this are fuzzed and tested under ASan. (It also tests the read that serves file
// systems which cannot map.)
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kMapFiles = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kMapFiles = false;
#else
constexpr bool kMapFiles = true;
#endif
#else
constexpr bool kMapFiles = true;
#endif

constexpr uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
constexpr uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
constexpr uint64_t kPrime3 = 0x165667B19E3779F9ull;

inline uint64_t rotl(uint64_t v, int r) { return (v << r) | (v >> (64 - r)); }
inline uint64_t lane(uint64_t acc, uint64_t w) { return rotl(acc + w * kPrime2, 31) * kPrime1; }
inline uint64_t load64(const uint8_t* p) {
  uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}
// Spreads every input bit over the output (the last step of the checksum).
inline uint64_t avalanche(uint64_t h) {
  h ^= h >> 33;
  h *= kPrime2;
  h ^= h >> 29;
  h *= kPrime3;
  h ^= h >> 32;
  return h;
}

template <typename T>
void put(std::string& out, size_t at, T value) {
  std::memcpy(&out[at], &value, sizeof value);
}
template <typename T>
T get(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// `size` bytes in a fresh 8-byte aligned buffer filled by `fill`, zero after the last byte up
// to the next multiple of 8 (not zeroed before: that would cost as much as the fill).
template <typename Fill>
std::shared_ptr<const uint8_t> alignedCopy(size_t size, Fill&& fill) {
  std::unique_ptr<uint64_t[]> words(new uint64_t[(size + 7) / 8]);
  if (size > 0) words[(size + 7) / 8 - 1] = 0;
  fill(reinterpret_cast<uint8_t*>(words.get()));
  return {reinterpret_cast<const uint8_t*>(words.release()),
          [](const uint8_t* p) { delete[] reinterpret_cast<const uint64_t*>(p); }};
}

}  // namespace

uint64_t contentChecksum(const uint8_t* data, size_t size) noexcept {
  uint64_t a = kPrime1 + kPrime2, b = kPrime2, c = 0, d = 0 - kPrime1;
  size_t i = 0;
  for (; i + 32 <= size; i += 32) {
    a = lane(a, load64(data + i));
    b = lane(b, load64(data + i + 8));
    c = lane(c, load64(data + i + 16));
    d = lane(d, load64(data + i + 24));
  }
  uint64_t h = rotl(a, 1) + rotl(b, 7) + rotl(c, 12) + rotl(d, 18) + size;
  for (; i + 8 <= size; i += 8) h = lane(h, load64(data + i));
  uint64_t tail = 0;
  std::memcpy(&tail, data + i, size - i);
  h = lane(h, tail ^ (static_cast<uint64_t>(size - i) << 59));
  return avalanche(h);
}

std::string framedFileBytes(std::string_view magic, uint32_t version, std::string_view body) {
  std::string out(kFrameBytes + body.size(), '\0');
  std::memcpy(&out[0], magic.data(), std::min<size_t>(magic.size(), 8));
  put<uint32_t>(out, 8, version);
  put<uint64_t>(out, 16, out.size());
  std::memcpy(&out[kFrameBytes], body.data(), body.size());
  put<uint64_t>(out, 24, contentChecksum(reinterpret_cast<const uint8_t*>(out.data()) + kFrameBytes, body.size()));
  return out;
}

FramedFile framedFileInMemory(std::string_view bytes, uint32_t version) {
  FramedFile file;
  file.size = bytes.size();
  file.version = version;
  file.storage = alignedCopy(bytes.size(), [&](uint8_t* dst) { std::memcpy(dst, bytes.data(), bytes.size()); });
  return file;
}

void repairChecksum(std::string& bytes) {
  if (bytes.size() < kFrameBytes) return;
  put<uint64_t>(bytes, 24,
                contentChecksum(reinterpret_cast<const uint8_t*>(bytes.data()) + kFrameBytes, bytes.size() - kFrameBytes));
}

FramedFile readFramedFile(const std::string& path, std::string_view magic, uint32_t maxVersion, uint64_t maxBytes,
                          const std::string& kind, const std::string& foreignHint) {
  const auto fail = [&](const std::string& problem) { return FileFormatError(path, problem); };
  if (const std::string problem = inputFileProblem(path); !problem.empty()) throw fail(problem);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw fail("cannot open: " + std::generic_category().message(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0) throw fail("cannot stat: " + std::generic_category().message(errno));
  const uint64_t size = static_cast<uint64_t>(info.st_size);
  if (size > maxBytes)
    throw fail("is " + std::to_string(size) + " bytes, more than a " + kind + " file may be (" +
               std::to_string(maxBytes) + ")");
  if (size < kFrameBytes)
    throw fail("truncated: " + std::to_string(size) + " bytes, shorter than the " + std::to_string(kFrameBytes) +
               "-byte header of a " + kind + " file");
  FramedFile file;
  file.size = static_cast<size_t>(size);
  // MAP_POPULATE: the checksum touches every page at once, so map them all in one call rather
  // than fault them in one by one.
  void* mapped = kMapFiles ? ::mmap(nullptr, file.size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0) : MAP_FAILED;
  if (mapped != MAP_FAILED) {
    const size_t length = file.size;
    file.storage.reset(static_cast<const uint8_t*>(mapped),
                       [length](const uint8_t* p) { ::munmap(const_cast<uint8_t*>(p), length); });
  } else {
    file.storage = alignedCopy(file.size, [&](uint8_t* dst) {
      size_t done = 0;
      while (done < file.size) {
        const ssize_t got = ::read(fd, dst + done, file.size - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw fail("cannot read: " + std::generic_category().message(errno));
        if (got == 0) throw fail("shrank while being read");
        done += static_cast<size_t>(got);
      }
    });
  }
  const uint8_t* p = file.bytes();
  if (std::memcmp(p, magic.data(), 8) != 0)
    throw fail("not a " + kind + " file (it does not start with " + std::string(magic) + ")" + foreignHint);
  file.version = get<uint32_t>(p + 8);
  if (file.version == 0 || file.version > maxVersion)
    throw fail(kind + " format version " + std::to_string(file.version) + " is not one this library reads (1.." +
               std::to_string(maxVersion) + ")");
  if (get<uint32_t>(p + 12) != 0) throw fail("damaged header: reserved field is not zero");
  const uint64_t declared = get<uint64_t>(p + 16);
  if (declared != size)
    throw fail(declared > size ? "truncated: " + std::to_string(size) + " bytes of the " + std::to_string(declared) +
                                     " its header declares"
                               : std::to_string(size) + " bytes, more than the " + std::to_string(declared) +
                                     " its header declares (trailing data)");
  if (get<uint64_t>(p + 24) != contentChecksum(file.body(), file.bodySize()))
    throw fail("damaged: checksum mismatch (the content changed after it was written)");
  return file;
}

}  // namespace mdbrief::internal
