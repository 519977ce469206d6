#include "cli/gzip_compression.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <zlib.h>

namespace mdbrief::cli {

std::string gzipCompress(std::string_view bytes, int level) {
  z_stream stream{};
  // 15 + 16: the largest window, wrapped as gzip rather than zlib.
  if (deflateInit2(&stream, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("gzip: cannot start the compressor");
  std::string out(deflateBound(&stream, static_cast<uLong>(bytes.size())), '\0');
  // zlib counts in 32 bits: larger inputs and outputs go in pieces.
  constexpr size_t kPiece = std::numeric_limits<uInt>::max();
  size_t in = 0;
  int result = Z_OK;
  while (result == Z_OK) {
    const size_t inPiece = std::min(kPiece, bytes.size() - in);
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + in));
    stream.avail_in = static_cast<uInt>(inPiece);
    stream.next_out = reinterpret_cast<Bytef*>(out.data() + stream.total_out);
    stream.avail_out = static_cast<uInt>(std::min(kPiece, out.size() - stream.total_out));
    const bool last = in + inPiece == bytes.size();
    result = deflate(&stream, last ? Z_FINISH : Z_NO_FLUSH);
    in += inPiece - stream.avail_in;
  }
  out.resize(stream.total_out);
  deflateEnd(&stream);
  if (result != Z_STREAM_END) throw std::runtime_error("gzip: compression failed");
  return out;
}

}  // namespace mdbrief::cli
