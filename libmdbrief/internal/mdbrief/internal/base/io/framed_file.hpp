#pragma once
// The frame of the library's binary files (the vocabulary and the database): a fixed header that
// names the kind, the version and the size, and a checksum of everything after it, so that a
// truncated, foreign, newer or damaged file is refused before its content is trusted. Shared
// with the fuzz targets, which repair the checksum of their inputs to reach the checks behind it.
//
// Layout, little-endian:
//   bytes  0-7   magic: 8 ASCII characters naming the kind (e.g. "MDBVOCAB")
//   bytes  8-11  u32 format version (1, 2, ...)
//   bytes 12-15  u32 zero
//   bytes 16-23  u64 size of the whole file in bytes
//   bytes 24-31  u64 contentChecksum of bytes 32 .. end
//   bytes 32-    the body, laid out by the kind
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mdbrief::internal {

inline constexpr size_t kFrameBytes = 32;

// A 64-bit checksum of `size` bytes (multiply-rotate over 64-bit words in four independent
// lanes, so it runs at memory speed). Detects damage, not tampering: it is not cryptographic.
uint64_t contentChecksum(const uint8_t* data, size_t size) noexcept;

// The bytes of a framed file: the header for `magic` (8 characters), `version` and `body`.
std::string framedFileBytes(std::string_view magic, uint32_t version, std::string_view body);

struct FramedFile {
  // The whole file, 8-byte aligned (the body's sections rely on it): a read-only private
  // mapping of the file (readFramedFile), or a copy in memory. Mapped, not read: a read's
  // copy into fresh pages was the largest part of loading a large vocabulary (docs/RESULTS.md
  // "Place recognition").
  std::shared_ptr<const uint8_t> storage;
  size_t size = 0;  // bytes
  uint32_t version = 0;
  const uint8_t* bytes() const { return storage.get(); }
  const uint8_t* body() const { return bytes() + kFrameBytes; }
  size_t bodySize() const { return size - kFrameBytes; }
};

// Maps `path` (or, where its file system cannot map it and under AddressSanitizer, reads it
// with one read) after checking, in this order, that it is a readable regular file of at most
// maxBytes, at least a header long, starts with `magic`, has a version in [1, maxVersion], a
// size field equal to its size and the right checksum. Throws FileFormatError naming the file
// and the first check that failed; `kind` names the file in messages ("vocabulary"),
// `foreignHint` is appended when the magic is wrong (may be empty).
// A mapped file must not be truncated or rewritten in place while the result lives (the
// process would get SIGBUS or see the new bytes); the library's writers replace files by
// renaming a new one over them (atomic_file.hpp), which leaves a mapping of the old intact.
FramedFile readFramedFile(const std::string& path, std::string_view magic, uint32_t maxVersion, uint64_t maxBytes,
                          const std::string& kind, const std::string& foreignHint);

// A framed file's bytes held in memory as a load would hold them (nothing checked).
FramedFile framedFileInMemory(std::string_view bytes, uint32_t version);

// Rewrites the checksum field of a framed file's bytes (at least kFrameBytes long; shorter
// ones are left as they are), for the fuzz targets.
void repairChecksum(std::string& bytes);

}  // namespace mdbrief::internal
