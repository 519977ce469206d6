#include "toolkit/storage_text.hpp"

#include <string_view>
#include <vector>

#include <zlib.h>

#include "mdbrief/internal/base/io/nesting.hpp"

namespace mdbrief {

StorageText scanStorageText(const std::string& path, std::uintmax_t limit) {
  StorageText text;
  gzFile in = gzopen(path.c_str(), "rb");
  if (!in) return text;
  std::vector<char> buffer(1 << 16);
  internal::NestingScan nesting;
  int n = 0;
  while (text.bytes <= limit && (n = gzread(in, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) {
    text.bytes += static_cast<std::uintmax_t>(n);
    if (!nesting.feed(std::string_view(buffer.data(), static_cast<size_t>(n)))) break;
  }
  gzclose(in);
  text.nesting = nesting.problem();
  return text;
}

}  // namespace mdbrief
