#pragma once
// What cv::FileStorage would parse from a file, checked before it does: OpenCV's parsers (XML,
// YAML, JSON) recurse once per nesting level and overflowed the stack on a file nested 100,000
// deep (issue 45), and read .gz files without bound.
#include <cstdint>
#include <string>

namespace mdbrief {

struct StorageText {
  std::uintmax_t bytes = 0;  // the text's size, counted up to the limit + 1
  std::string nesting;       // internal::NestingScan's problem, or ""
};

// The text of path as cv::FileStorage reads it (a .gz decompressed; zlib reads any other file as
// it is), counted up to `limit` + 1 bytes and scanned for nesting deeper than
// internal::kMaxNesting. A file that cannot be opened or a damaged stream stops the scan
// (cv::FileStorage then reports it).
StorageText scanStorageText(const std::string& path, std::uintmax_t limit);

}  // namespace mdbrief
