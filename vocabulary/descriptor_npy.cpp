#include "vocabulary/descriptor_npy.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"

namespace mdbrief::vocab {

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr uint64_t kMaxNpyBytes = uint64_t{2} << 30;
constexpr size_t kMaxHeaderBytes = size_t{1} << 20;

// The text after `key`'s colon in the header's dictionary, or npos.
size_t valueOf(const std::string& header, const std::string& key) {
  for (const char quote : {'\'', '"'}) {
    const size_t at = header.find(quote + key + quote);
    if (at == std::string::npos) continue;
    size_t colon = header.find_first_not_of(" ", at + key.size() + 2);
    if (colon == std::string::npos || header[colon] != ':') return std::string::npos;
    return header.find_first_not_of(" ", colon + 1);
  }
  return std::string::npos;
}

}  // namespace

cv::Mat readDescriptorNpy(const std::string& path) {
  const auto fail = [&](const std::string& problem) { return FileFormatError(path, problem); };
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty()) throw fail(problem);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw fail("cannot read its size: " + ec.message());
  if (size > kMaxNpyBytes) throw fail("is " + std::to_string(size) + " bytes, more than a descriptor file may be");
  std::ifstream in(path, std::ios::binary);
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) throw fail("cannot read all of it");
  if (size < 10 || std::memcmp(bytes.data(), kMagic, 6) != 0) throw fail("not a NumPy .npy file (no \\x93NUMPY magic)");
  const int major = static_cast<uint8_t>(bytes[6]);
  if (major < 1 || major > 3) throw fail(".npy format version " + std::to_string(major) + " is not 1, 2 or 3");
  size_t headerLength = 0, headerStart = 10;
  if (major == 1) {
    headerLength = static_cast<uint8_t>(bytes[8]) | static_cast<size_t>(static_cast<uint8_t>(bytes[9])) << 8;
  } else {
    if (size < 12) throw fail("truncated .npy header");
    for (int b = 3; b >= 0; --b) headerLength = headerLength << 8 | static_cast<uint8_t>(bytes[8 + b]);
    headerStart = 12;
  }
  if (headerLength > kMaxHeaderBytes || headerStart + headerLength > size)
    throw fail("its header of " + std::to_string(headerLength) + " bytes does not fit in the file");
  const std::string header = bytes.substr(headerStart, headerLength);
  const size_t descr = valueOf(header, "descr");
  if (descr == std::string::npos) throw fail("the header has no 'descr'");
  const std::string type = header.substr(descr, header.find_first_of(",}", descr) - descr);
  if (type != "'|u1'" && type != "'<u1'" && type != "'>u1'" && type != "'u1'")
    throw fail("dtype " + type.substr(0, 16) + " is not uint8 ('|u1')");
  const size_t fortran = valueOf(header, "fortran_order");
  if (fortran == std::string::npos || header.compare(fortran, 5, "False") != 0)
    throw fail("not in C order (fortran_order must be False)");
  const size_t shape = valueOf(header, "shape");
  if (shape == std::string::npos || header[shape] != '(') throw fail("the header has no 'shape' tuple");
  const size_t close = header.find(')', shape);
  if (close == std::string::npos) throw fail("the header's shape is not closed");
  const std::string shapeText = header.substr(shape, close - shape + 1);
  // A dimension or a product beyond 64 bits is a shape too large for any file, said as such: the
  // product wrapped around (issue 45: (2^62 + 2400, 4) "needs 9600 data bytes, the file has 9600").
  const uint64_t data = size - headerStart - headerLength;
  const auto tooLarge = [&] {
    return fail("shape " + shapeText + " is too large: 2^64 bytes or more (the file has " + std::to_string(data) +
                " data bytes)");
  };
  std::vector<uint64_t> dims;
  for (size_t p = shape + 1; p < close;) {
    while (p < close && (header[p] == ' ' || header[p] == ',')) ++p;
    if (p >= close) break;
    uint64_t v = 0;
    const auto r = std::from_chars(header.data() + p, header.data() + close, v);
    if (r.ec == std::errc::result_out_of_range && dims.size() < 2) throw tooLarge();
    if (r.ec != std::errc() || dims.size() == 2) throw fail("shape " + shapeText + " is not (N, B)");
    dims.push_back(v);
    p = static_cast<size_t>(r.ptr - header.data());
  }
  if (dims.size() != 2) throw fail("shape " + shapeText + " is not (N, B)");
  const uint64_t rows = dims[0], cols = dims[1];
  if (cols < 4 || cols > 64 || cols % 4)
    throw fail(std::to_string(cols) + " bytes per descriptor: binary descriptors of 4..64 bytes in steps of 4 only");
  if (rows > UINT64_MAX / cols) throw tooLarge();
  if (rows * cols != data)
    throw fail("shape (" + std::to_string(rows) + ", " + std::to_string(cols) + ") needs " +
               std::to_string(rows * cols) + " data bytes, the file has " + std::to_string(data));
  if (rows > 0x7FFFFFFFu) throw fail("more than 2^31 descriptors");
  cv::Mat out(static_cast<int>(rows), static_cast<int>(cols), CV_8UC1);
  if (data) std::memcpy(out.data, bytes.data() + headerStart + headerLength, data);
  return out;
}

std::string descriptorNpyBytes(const cv::Mat& descriptors) {
  if (descriptors.type() != CV_8UC1 || !descriptors.isContinuous())
    throw std::invalid_argument("descriptorNpyBytes: need a continuous CV_8UC1 matrix");
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" + std::to_string(descriptors.rows) + ", " +
                       std::to_string(descriptors.cols) + "), }";
  // Padded with spaces and a newline so the data starts at a multiple of 64 bytes, as numpy does.
  const size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  std::string out(kMagic, 6);
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(header.size() & 0xFF);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  out.append(reinterpret_cast<const char*>(descriptors.data), descriptors.total());
  return out;
}

}  // namespace mdbrief::vocab
