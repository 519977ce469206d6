#include "cli/storage_io.hpp"

#include <array>
#include <fstream>
#include <iterator>
#include <vector>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "cli/commands.hpp"
#include "mdbrief/pattern_io.hpp"

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

// yaml-cpp recurses once per nesting level: bound the depth before it parses.
constexpr int kMaxFlowDepth = 64;

void requireWellFormedYaml(const std::string& path, const std::string& bytes) {
  int depth = 0;
  for (const char c : bytes) {
    depth += (c == '[' || c == '{') - (c == ']' || c == '}');
    if (depth > kMaxFlowDepth)
      throw InputError(path + ": brackets nested deeper than " + std::to_string(kMaxFlowDepth));
  }
  // OpenCV's "%YAML:1.0" first line is not a YAML 1.2 directive.
  const size_t start = bytes.rfind("%YAML:", 0) == 0 ? bytes.find('\n') : std::string::npos;
  try {
    YAML::Load(start == std::string::npos ? bytes : bytes.substr(start + 1));
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not well-formed YAML/JSON: " + e.what());
  }
}

void checkFolder(const fs::path& path) {
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(path.string() + ": the output folder " + folder.string() + " does not exist");
}

}  // namespace

void checkStorageOutput(const fs::path& path) {
  checkFolder(path);
  if (storageExtension(path).empty())
    throw InputError(path.string() + ": the output must end in .yml, .yaml, .json or .xml (optionally .gz)");
}

void checkImageOutput(const fs::path& path) {
  checkFolder(path);
  if (!cv::haveImageWriter(path.string()))
    throw InputError(path.string() + ": no image writer for this extension (use .png)");
}

void writeStorageAtomically(const fs::path& path, const std::function<void(cv::FileStorage&)>& write) {
  checkStorageOutput(path);
  const std::string ext = storageExtension(path);
  const std::string name = path.filename().string();
  // The temporary keeps the extension: FileStorage picks the format (and compression) from it.
  const fs::path temp = path.parent_path() / ("." + name.substr(0, name.size() - ext.size()) + ".tmp" +
                                              std::to_string(::getpid()) + ext);
  try {
    cv::FileStorage storage(temp.string(), cv::FileStorage::WRITE);
    if (!storage.isOpened()) throw InputError(path.string() + ": cannot create the output file");
    write(storage);
    storage.release();
  } catch (const cv::Exception& e) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw InputError(path.string() + ": writing failed: " + e.err);
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw InputError(path.string() + ": cannot rename the temporary output into place");
  }
}

void writeImageAtomically(const fs::path& path, const cv::Mat& image) {
  checkImageOutput(path);
  std::vector<uchar> bytes;
  if (!cv::imencode(path.extension().string(), image, bytes))
    throw InputError(path.string() + ": encoding the image failed");
  try {
    writeFileAtomically(path, std::string(bytes.begin(), bytes.end()));
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

void writeFeatureFile(const fs::path& path, const Features& features) {
  writeStorageAtomically(path, [&](cv::FileStorage& storage) {
    cv::write(storage, "keypoints", features.keypoints);
    storage << "descriptors" << features.descriptors;
    if (!features.masks.empty()) storage << "masks" << features.masks;
  });
}

cv::FileStorage openStorageForReading(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  if (!endsWith(path, ".gz")) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) throw InputError(path + ": cannot read");
    const size_t nul = bytes.find('\0');
    if (nul != std::string::npos)
      throw InputError(path + ": byte " + std::to_string(nul) +
                       " is NUL; a FileStorage text file (YAML, JSON, XML) cannot hold one");
    const std::string ext = storageExtension(path);
    if (ext != ".xml") requireWellFormedYaml(path, bytes);
  }
  cv::FileStorage storage(path, cv::FileStorage::READ);
  if (!storage.isOpened()) throw InputError(path + ": cannot open as an OpenCV FileStorage file");
  return storage;
}

Features readFeatureFile(const std::string& path) {
  Features f;
  try {
    cv::FileStorage storage = openStorageForReading(path);
    const cv::FileNode desc = storage["descriptors"];
    if (desc.empty()) throw InputError(path + ": no node 'descriptors'");
    desc >> f.descriptors;
    if (!storage["masks"].empty()) storage["masks"] >> f.masks;
    if (!storage["keypoints"].empty()) cv::read(storage["keypoints"], f.keypoints);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot parse: " + e.err);
  }
  const cv::Mat& d = f.descriptors;
  if (!d.empty() && (d.type() != CV_8UC1 || d.cols % 4 != 0 || d.cols > 64))
    throw InputError(path + ": 'descriptors' must be N x bytes CV_8U with bytes a multiple of 4 in [4, 64]");
  if (!f.masks.empty() && (f.masks.type() != CV_8UC1 || f.masks.size() != d.size()))
    throw InputError(path + ": 'masks' must have the size and type of 'descriptors'");
  if (!f.keypoints.empty() && static_cast<int>(f.keypoints.size()) != d.rows)
    throw InputError(path + ": " + std::to_string(f.keypoints.size()) + " keypoints but " + std::to_string(d.rows) +
                     " descriptor rows");
  return f;
}

}  // namespace mdbrief::cli
