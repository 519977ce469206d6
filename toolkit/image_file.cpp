#include "toolkit/image_file.hpp"

#include <algorithm>
#include <array>
#include <csetjmp>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include <jpeglib.h>
#include <opencv2/imgcodecs.hpp>

#include "mdbrief/internal/base/io/atomic_file.hpp"

namespace mdbrief {

std::string truncationProblem(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return "cannot read the file";
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const auto startsWith = [&](std::initializer_list<unsigned char> sig) {
    return bytes.size() >= sig.size() && std::equal(sig.begin(), sig.end(), bytes.begin());
  };
  if (startsWith({0xFF, 0xD8})) {
    size_t end = bytes.size();
    while (end > 2 && bytes[end - 1] == 0) --end;  // some writers pad after EOI
    return end >= 4 && bytes[end - 2] == 0xFF && bytes[end - 1] == 0xD9
               ? ""
               : "truncated JPEG (no end-of-image marker): only part of it can be decoded";
  }
  if (startsWith({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A})) {
    static const std::array<unsigned char, 12> iend{0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    return bytes.size() >= 8 + iend.size() && std::equal(iend.begin(), iend.end(), bytes.end() - iend.size())
               ? ""
               : "truncated PNG (no IEND chunk): only part of it can be decoded";
  }
  return "";
}

namespace {

uint32_t bigEndian(const unsigned char* p, int bytes) {
  uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// The width and height a PNG's IHDR or a JPEG's first SOF marker declares, {0, 0} if none.
std::pair<uint64_t, uint64_t> declaredSize(const std::vector<unsigned char>& b) {
  static const unsigned char kPng[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (b.size() >= 24 && std::equal(std::begin(kPng), std::end(kPng), b.begin()) &&
      std::equal(b.begin() + 12, b.begin() + 16, "IHDR"))
    return {bigEndian(&b[16], 4), bigEndian(&b[20], 4)};
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return {0, 0};
  for (size_t i = 2; i + 9 < b.size() && b[i] == 0xFF;) {
    const unsigned char marker = b[i + 1];
    // SOF0..SOF15 but DHT (C4), JPG (C8) and DAC (CC): precision, height, width.
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC)
      return {bigEndian(&b[i + 7], 2), bigEndian(&b[i + 5], 2)};
    i += 2 + bigEndian(&b[i + 2], 2);
  }
  return {0, 0};
}

uint64_t limitFromEnvironment(const char* name, uint64_t fallback) {
  const char* value = std::getenv(name);
  if (!value || !*value) return fallback;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(value, &end, 10);
  return *end == '\0' && v > 0 ? v : fallback;
}

}  // namespace

namespace {

// libjpeg's error manager, recording instead of printing: the first warning, or the error that
// ended the decoding (longjmp back to jpegDataProblem).
struct RecordingErrors {
  jpeg_error_mgr manager;
  std::jmp_buf escape;
  char message[JMSG_LENGTH_MAX];
  bool recorded;
};

void recordMessage(j_common_ptr info, int level) {
  auto* errors = reinterpret_cast<RecordingErrors*>(info->err);
  if (level < 0 && !errors->recorded) {  // a warning (level >= 0: trace messages)
    info->err->format_message(info, errors->message);
    errors->recorded = true;
  }
}

[[noreturn]] void recordErrorAndEscape(j_common_ptr info) {
  auto* errors = reinterpret_cast<RecordingErrors*>(info->err);
  info->err->format_message(info, errors->message);
  errors->recorded = true;
  std::longjmp(errors->escape, 1);
}

// Decodes the whole JPEG to grey, every scanline, so that libjpeg meets every damaged segment.
// Only C objects live between setjmp and longjmp; the row is libjpeg's, freed with it.
std::string decodeJpegRecording(const std::vector<unsigned char>& bytes) {
  jpeg_decompress_struct info{};
  RecordingErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.emit_message = recordMessage;
  errors.manager.error_exit = recordErrorAndEscape;
  if (setjmp(errors.escape) == 0) {
    jpeg_create_decompress(&info);
    jpeg_mem_src(&info, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&info, TRUE);
    info.out_color_space = JCS_GRAYSCALE;
    jpeg_start_decompress(&info);
    JSAMPARRAY row = (*info.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&info), JPOOL_IMAGE,
                                               info.output_width * info.output_components, 1);
    while (info.output_scanline < info.output_height) jpeg_read_scanlines(&info, row, 1);
    jpeg_finish_decompress(&info);
  }
  jpeg_destroy_decompress(&info);
  return errors.recorded ? errors.message : "";
}

}  // namespace

std::string jpegDataProblem(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (bytes.size() < 2 || bytes[0] != 0xFF || bytes[1] != 0xD8) return "";
  return decodeJpegRecording(bytes);
}

std::string imageSizeProblem(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::vector<unsigned char> head(1 << 16);  // the SOF marker follows the tables, well within it
  f.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(f.gcount()));
  const auto [width, height] = declaredSize(head);
  // OpenCV's defaults (imgcodecs/src/loadsave.cpp), changed by the same variables.
  const uint64_t maxPixels = limitFromEnvironment("CV_IO_MAX_IMAGE_PIXELS", uint64_t{1} << 30);
  const uint64_t maxWidth = limitFromEnvironment("CV_IO_MAX_IMAGE_WIDTH", uint64_t{1} << 20);
  const uint64_t maxHeight = limitFromEnvironment("CV_IO_MAX_IMAGE_HEIGHT", uint64_t{1} << 20);
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width > maxWidth || height > maxHeight)
    return size + ", over the " + std::to_string(maxWidth) + "x" + std::to_string(maxHeight) +
           " OpenCV decodes (CV_IO_MAX_IMAGE_WIDTH, CV_IO_MAX_IMAGE_HEIGHT)";
  if (width * height > maxPixels)
    return size + " = " + std::to_string(width * height) + " pixels, over the " + std::to_string(maxPixels) +
           " OpenCV decodes (CV_IO_MAX_IMAGE_PIXELS)";
  return "";
}

cv::Mat decodeGreyImage(const std::filesystem::path& path) {
  try {
    return cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    return {};  // some decoders throw on damaged files instead of returning nothing
  }
}

void writeImageAtomically(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  bool encoded = false;
  try {
    encoded = cv::imencode(path.extension().string(), image, bytes);
  } catch (const cv::Exception&) {
  }
  if (!encoded) throw std::runtime_error(path.string() + ": cannot encode the image in this format");
  internal::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace mdbrief
