#pragma once
// gzip compression in memory, for the .gz FileStorage outputs: OpenCV compresses only what it
// writes to a file itself, and those writes go unchecked (storage_io.cpp writes through the
// checked atomic writer instead).
#include <string>
#include <string_view>

namespace mdbrief::cli {

// bytes as one gzip member (RFC 1952) at zlib's compression level (1 fastest .. 9 smallest).
// The header carries no name and no time, so the same bytes give the same output.
std::string gzipCompress(std::string_view bytes, int level);

}  // namespace mdbrief::cli
