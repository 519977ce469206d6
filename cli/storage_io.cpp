#include "cli/storage_io.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include "cli/commands.hpp"
#include "cli/gzip_compression.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "mdbrief/internal/base/io/nesting.hpp"
#include "mdbrief/internal/base/io/unique_keys.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "toolkit/storage_text.hpp"

namespace mdbrief::cli {
namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The FileStorage extension of the file name ("" if none), longest first so .yml.gz wins.
std::string storageExtension(const fs::path& path) {
  static const std::array<const char*, 8> kExtensions = {".yml.gz", ".yaml.gz", ".json.gz", ".xml.gz",
                                                         ".yml",    ".yaml",    ".json",    ".xml"};
  const std::string name = path.filename().string();
  for (const char* ext : kExtensions)
    if (endsWith(name, ext) && name.size() > std::string(ext).size()) return ext;
  return "";
}

YAML::Node parseYaml(const std::string& path, const std::string& bytes) {
  const size_t nul = bytes.find('\0');
  if (nul != std::string::npos)
    throw InputError(path + ": byte " + std::to_string(nul) +
                     " is NUL; a FileStorage text file (YAML, JSON, XML) cannot hold one");
  // yaml-cpp recurses once per nesting level, and says only "bad file" at its own limit.
  if (const std::string nesting = internal::nestingProblem(bytes); !nesting.empty())
    throw InputError(path + ": " + nesting);
  // OpenCV's "%YAML:1.0" first line is not a YAML 1.2 directive.
  const size_t start = bytes.rfind("%YAML:", 0) == 0 ? bytes.find('\n') : std::string::npos;
  YAML::Node root;
  try {
    root = YAML::Load(start == std::string::npos ? bytes : bytes.substr(start + 1));
  } catch (const YAML::DeepRecursion& e) {
    throw InputError(path + ": nested deeper than the parser follows (line " +
                     std::to_string(e.mark.line + 1 + (start == std::string::npos ? 0 : 1)) + ")");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not well-formed YAML/JSON: " + e.what());
  }
  if (!root.IsMap()) throw InputError(path + ": not a FileStorage file (the top level is not a map of named nodes)");
  try {
    internal::requireUniqueYamlKeys(path, root, bytes.size());
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
  return root;
}

// A scalar as a number: YAML's ".inf" and ".nan" spellings and OpenCV's ".Nan" too, so that
// the caller can report a non-finite value as such.
double number(const YAML::Node& node, const std::string& where) {
  if (!node.IsScalar()) throw InputError(where + ": expected a number");
  if (node.Scalar() == ".Nan") return std::numeric_limits<double>::quiet_NaN();
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(where + ": '" + node.Scalar() + "' is not a number");
  }
}

int integer(const YAML::Node& node, const std::string& where) {
  const double v = number(node, where);
  if (!(v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()) || v != std::floor(v))
    throw InputError(where + ": " + node.Scalar() + " is not an int");
  return static_cast<int>(v);
}

cv::KeyPoint keypointFrom(const std::vector<YAML::Node>& v, const std::string& where) {
  return cv::KeyPoint(static_cast<float>(number(v[0], where)), static_cast<float>(number(v[1], where)),
                      static_cast<float>(number(v[2], where)), static_cast<float>(number(v[3], where)),
                      static_cast<float>(number(v[4], where)), integer(v[5], where), integer(v[6], where));
}

std::string mebibytes(std::uintmax_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

// Refuses text over the parser's limit before it is parsed (a 10-million-keypoint file ran
// yaml-cpp out of memory after minutes), and the text of OpenCV's parsers nested too deep (the
// yaml-cpp path checks the text it reads).
void checkText(const std::string& path, const std::string& ext) {
  std::error_code ec;
  if (ext == ".yml" || ext == ".yaml" || ext == ".json") {
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (!ec && bytes > kMaxYamlCppTextBytes)
      throw InputError(path + ": " + std::to_string(bytes) + " bytes, over the " + mebibytes(kMaxYamlCppTextBytes) +
                       " a YAML or JSON file may have (.xml or .gz files may hold up to " +
                       mebibytes(kMaxOpenCvTextBytes) + " of text)");
    return;
  }
  const std::string overLimit =
      path + ": over the " + mebibytes(kMaxOpenCvTextBytes) + " of text an .xml or .gz file may hold";
  const bool compressed = endsWith(ext, ".gz");
  if (!compressed) {
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (!ec && bytes > kMaxOpenCvTextBytes) throw InputError(overLimit);
  }
  const StorageText text = scanStorageText(path, kMaxOpenCvTextBytes);
  if (text.bytes > kMaxOpenCvTextBytes) throw InputError(overLimit + " once decompressed");
  if (!text.nesting.empty()) throw InputError(path + ": " + text.nesting);
}

// The atomic writer's checks (folder, a regular file or none, writable) as an InputError.
void checkWritable(const fs::path& path) {
  try {
    internal::checkOutputPath(path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace

void checkStorageOutput(const fs::path& path) {
  if (storageExtension(path).empty())
    throw InputError(path.string() + ": the output must end in .yml, .yaml, .json or .xml (optionally .gz)");
  checkWritable(path);
}

void checkImageOutput(const fs::path& path) {
  if (!cv::haveImageWriter(path.string()))
    throw InputError(path.string() + ": no image writer for this extension (use .png)");
  checkWritable(path);
}

void checkOutputsApart(const std::vector<fs::path>& inputs, const std::vector<fs::path>& outputs) {
  try {
    internal::checkOutputsApart(inputs, outputs);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

namespace {

// The bytes of the FileStorage file `write` makes, in path's format.
std::string storageBytes(const fs::path& path, const std::function<void(cv::FileStorage&)>& write) {
  checkStorageOutput(path);
  const std::string extension = storageExtension(path);
  const bool compressed = endsWith(extension, ".gz");
  std::string bytes;
  try {
    // FileStorage's own file writes go unchecked: it writes to memory (the name only picks the
    // format) and the bytes go through the checked atomic writer.
    cv::FileStorage storage(compressed ? extension.substr(0, extension.size() - 3) : extension,
                            cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    write(storage);
    bytes = storage.releaseAndGetString();
  } catch (const cv::Exception& e) {
    throw InputError(path.string() + ": writing failed: " + e.err);
  }
  // Level 3 is what FileStorage uses for .gz files it writes itself: the same bytes as before.
  return compressed ? gzipCompress(bytes, 3) : bytes;
}

void writeFeatures(cv::FileStorage& storage, const Features& features) {
  cv::write(storage, "keypoints", features.keypoints);
  storage << "descriptors" << features.descriptors;
  if (!features.masks.empty()) storage << "masks" << features.masks;
  const Provenance& p = features.provenance;
  if (!p.testSet.empty()) storage << "test_set" << p.testSet << "test_set_digest" << p.testSetDigest;
  if (!p.cameraDigest.empty()) storage << "camera_digest" << p.cameraDigest;
  if (!p.pyramid.empty()) storage << "pyramid" << p.pyramid;
  if (!p.imageSize.empty()) storage << "image_size" << p.imageSize << "image_digest" << p.imageDigest;
}

}  // namespace

void writeStorageAtomically(const fs::path& path, const std::function<void(cv::FileStorage&)>& write) {
  const std::string bytes = storageBytes(path, write);
  try {
    internal::writeFileAtomically(path, bytes);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

void writeImageAtomically(const fs::path& path, const cv::Mat& image) {
  checkImageOutput(path);
  std::vector<uchar> bytes;
  if (!cv::imencode(path.extension().string(), image, bytes))
    throw InputError(path.string() + ": encoding the image failed");
  try {
    internal::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

void writeFeatureFiles(const std::vector<fs::path>& paths, const std::vector<Features>& features) {
  std::vector<internal::FileContent> files;
  for (size_t i = 0; i < paths.size(); ++i)
    files.push_back({paths[i], storageBytes(paths[i], [&](cv::FileStorage& s) { writeFeatures(s, features[i]); })});
  try {
    internal::writeFilesAtomically(files);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

struct StorageReader::Parsed {
  YAML::Node yaml;          // YAML and JSON
  cv::FileStorage storage;  // XML and .gz
};

StorageReader::StorageReader(const std::string& path) : path_(path), parsed_(std::make_unique<Parsed>()) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw InputError(path + ": " + problem);
  const std::string ext = storageExtension(path);
  checkText(path, ext);
  if (ext == ".yml" || ext == ".yaml" || ext == ".json") {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) throw InputError(path + ": cannot read");
    parsed_->yaml = parseYaml(path, bytes);
    return;
  }
  try {
    parsed_->storage.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot parse: " + e.err);
  }
  if (!parsed_->storage.isOpened()) throw InputError(path + ": cannot open as an OpenCV FileStorage file");
}

StorageReader::~StorageReader() = default;

bool StorageReader::has(const std::string& key) const {
  if (!parsed_->storage.isOpened()) {
    const YAML::Node node = std::as_const(parsed_->yaml)[key];
    return node && !node.IsNull();
  }
  return !parsed_->storage[key].empty();
}

namespace {

// A keypoint list of a YAML or JSON file (StorageReader::keypoints).
std::vector<cv::KeyPoint> yamlKeypoints(const YAML::Node& root, const std::string& key, const std::string& where) {
  std::vector<cv::KeyPoint> out;
  const YAML::Node node = root[key];
  if (!node || node.IsNull()) return out;
  if (!node.IsSequence()) throw InputError(where + ": expected a sequence of keypoints");
  std::vector<YAML::Node> flat;
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    if (item.IsSequence()) {
      if (item.size() != 7)
        throw InputError(where + ": keypoint " + std::to_string(i) + " has " + std::to_string(item.size()) +
                         " values, not 7 (x, y, size, angle, response, octave, class_id)");
      std::vector<YAML::Node> v(item.begin(), item.end());
      out.push_back(keypointFrom(v, where + ", keypoint " + std::to_string(i)));
    } else {
      flat.push_back(item);
    }
  }
  if (!flat.empty()) {
    if (!out.empty() || flat.size() % 7 != 0)
      throw InputError(where + ": a flat keypoint list needs 7 numbers per keypoint, got " +
                       std::to_string(flat.size()));
    for (size_t i = 0; i < flat.size(); i += 7)
      out.push_back(keypointFrom({flat.begin() + static_cast<long>(i), flat.begin() + static_cast<long>(i) + 7},
                                 where + ", keypoint " + std::to_string(i / 7)));
  }
  return out;
}

}  // namespace

std::vector<cv::KeyPoint> StorageReader::keypoints(const std::string& key) const {
  const std::string where = path_ + ": node '" + key + "'";
  std::vector<cv::KeyPoint> out;
  if (parsed_->storage.isOpened()) {
    try {
      cv::read(parsed_->storage[key], out);
    } catch (const cv::Exception& e) {
      throw InputError(where + ": " + e.err);
    }
  } else {
    out = yamlKeypoints(parsed_->yaml, key, where);
  }
  // Whatever reads them next would drop a keypoint at a NaN or infinite position without a word
  // (match --inliers did, issue 45).
  for (size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i].pt.x) || !std::isfinite(out[i].pt.y)) {
      std::ostringstream at;
      at << "(" << out[i].pt.x << ", " << out[i].pt.y << ")";
      throw InputError(where + ": keypoint " + std::to_string(i) + " at " + at.str() +
                       ": a keypoint needs a finite position");
    }
  return out;
}

cv::Mat StorageReader::matrix(const std::string& key) const {
  const std::string where = path_ + ": node '" + key + "'";
  cv::Mat out;
  if (parsed_->storage.isOpened()) {
    try {
      parsed_->storage[key] >> out;
    } catch (const cv::Exception& e) {
      throw InputError(where + ": " + e.err);
    }
    return out;
  }
  const YAML::Node node = std::as_const(parsed_->yaml)[key];
  if (!node || node.IsNull()) return out;
  if (!node.IsMap() || !node["rows"] || !node["cols"] || !node["dt"] || !node["data"])
    throw InputError(where + ": expected an opencv-matrix (rows, cols, dt, data)");
  const int rows = integer(node["rows"], where + ", rows");
  const int cols = integer(node["cols"], where + ", cols");
  const YAML::Node data = node["data"];
  if (rows < 0 || cols < 0 || !data.IsSequence() || data.size() != static_cast<size_t>(rows) * static_cast<size_t>(cols))
    throw InputError(where + ": rows x cols must be the number of values in data");
  static const std::string kCodes = "ucwsifd";
  static const int kTypes[] = {CV_8U, CV_8S, CV_16U, CV_16S, CV_32S, CV_32F, CV_64F};
  const std::string dt = node["dt"].IsScalar() ? node["dt"].Scalar() : "";
  if (dt.size() != 1 || kCodes.find(dt[0]) == std::string::npos)
    throw InputError(where + ": dt '" + dt + "' is not a single-channel type (u, c, w, s, i, f, d)");
  const int type = kTypes[kCodes.find(dt[0])];
  if (rows * cols == 0) return cv::Mat(rows, cols, type);  // the shape tells N x 0 from 0 x 0
  cv::Mat values(rows, cols, CV_64F);
  for (int i = 0; i < rows * cols; ++i)
    values.at<double>(i / cols, i % cols) = number(data[static_cast<size_t>(i)], where + ", value " + std::to_string(i));
  if (type != CV_32F && type != CV_64F) {
    cv::Mat rounded;
    values.convertTo(rounded, type);
    cv::Mat back;
    rounded.convertTo(back, CV_64F);
    if (cv::norm(back, values, cv::NORM_INF) != 0.0)
      throw InputError(where + ": a value does not fit dt '" + dt + "'");
    return rounded;
  }
  values.convertTo(out, type);
  return out;
}

std::string StorageReader::text(const std::string& key) const {
  if (parsed_->storage.isOpened()) {
    const cv::FileNode node = parsed_->storage[key];
    if (node.empty()) return "";
    if (!node.isString()) throw InputError(path_ + ": node '" + key + "': expected text");
    return node.string();
  }
  const YAML::Node node = std::as_const(parsed_->yaml)[key];
  if (!node || node.IsNull()) return "";
  if (!node.IsScalar()) throw InputError(path_ + ": node '" + key + "': expected text");
  return node.Scalar();
}

Features readFeatureFile(const std::string& path) {
  Features f;
  const StorageReader storage(path);
  f.provenance = {storage.text("test_set"), storage.text("test_set_digest"), storage.text("camera_digest"),
                  storage.text("pyramid"),  storage.text("image_size"),      storage.text("image_digest")};
  if (!storage.has("descriptors")) throw InputError(path + ": no node 'descriptors'");
  f.descriptors = storage.matrix("descriptors");
  f.masks = storage.matrix("masks");
  f.keypoints = storage.keypoints("keypoints");
  const cv::Mat& d = f.descriptors;
  // 0 x 0 and 0 x bytes hold no descriptors; N x 0 holds descriptors of no bits.
  if (d.rows > 0 && (d.type() != CV_8UC1 || d.cols < 4 || d.cols % 4 != 0 || d.cols > 64))
    throw InputError(path + ": 'descriptors' must be N x bytes CV_8U with bytes a multiple of 4 in [4, 64], got " +
                     internal::matrixText(d));
  if (!f.masks.empty() && (f.masks.type() != CV_8UC1 || f.masks.size() != d.size()))
    throw InputError(path + ": 'masks' must have the size and type of 'descriptors' (" + internal::matrixText(d) +
                     "), got " + internal::matrixText(f.masks));
  if (!f.keypoints.empty() && static_cast<int>(f.keypoints.size()) != d.rows)
    throw InputError(path + ": " + std::to_string(f.keypoints.size()) + " keypoints but " + std::to_string(d.rows) +
                     " descriptor rows");
  return f;
}

}  // namespace mdbrief::cli
