#include "mdbrief/camera/io.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/registry.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/ocam.hpp"
#include "mdbrief/camera/rig.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "mdbrief/internal/base/io/nesting.hpp"
#include "mdbrief/internal/base/io/unique_keys.hpp"

namespace mdbrief {
namespace {

using detail::findModelFormat;
using detail::makeOcam;
using detail::modelFormats;
using detail::ModelFormat;
using detail::modelNameList;
using detail::YamlReader;

// The model's keys of r (the image size read by the caller), nothing else.
std::shared_ptr<Camera> readModel(const std::string& source, const YamlReader& r, const std::string& model, int width,
                                  int height, const std::set<std::string>& alsoAllowed) {
  const ModelFormat* format = findModelFormat(model);
  if (!format) r.fail("model", "names an unknown model '" + model + "' (known: " + modelNameList() + ")");
  std::set<std::string> allowed = format->keys;
  allowed.insert(alsoAllowed.begin(), alsoAllowed.end());
  r.requireOnly(allowed, model);
  return format->read(source, r, width, height);
}

std::shared_ptr<Camera> loadProjectYaml(const std::string& path, const YamlReader& r) {
  const YAML::Node modelNode = r.node("model");
  if (!modelNode.IsScalar()) r.fail("model", "must be a model name");
  const int width = r.size("width"), height = r.size("height");
  return readModel(path, r, modelNode.Scalar(), width, height, {"model", "width", "height"});
}

std::shared_ptr<Camera> loadCalibAdapterYaml(const std::string& path, const YamlReader& root) {
  const YamlReader image = root.sub("image");
  const int width = image.size("width"), height = image.size("height");
  const YamlReader r = root.sub("parameter");
  std::set<std::string> keys = r.keys();

  if (keys.count("coefficients")) {
    const YamlReader coefficients = r.sub("coefficients");
    OcamParams p;
    p.width = width;
    p.height = height;
    p.forward = coefficients.numbers("unprojection");
    p.inverse = coefficients.numbers("projection");
    p.c = r.number("c");
    p.d = r.number("d");
    p.e = r.number("e");
    p.u0 = r.number("cx");  // cx is the column, cy the row
    p.v0 = r.number("cy");
    return makeOcam(path, p);
  }
  detail::readIntrinsics(r, width, height);  // a missing or bad fx fy cx cy is reported first
  for (const char* key : {"fx", "fy", "cx", "cy"}) keys.erase(key);
  for (const ModelFormat& format : modelFormats())
    for (const std::set<std::string>& distortion : format.adapterKeys)
      if (keys == distortion) return format.read(path, r, width, height);
  std::string list;
  for (const std::string& key : keys) list += (list.empty() ? "" : ", ") + key;
  throw std::runtime_error(path + ": key 'parameter' has distortion keys {" + list +
                           "} that match no known model");
}

// Splits the non-comment lines of an OCamCalib calib_results.txt into number rows.
std::vector<std::vector<std::string>> ocamTextRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream tokens(line);
    std::vector<std::string> row;
    for (std::string t; tokens >> t;) row.push_back(t);
    rows.push_back(row);
  }
  return rows;
}

bool parseNumber(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end != token.c_str() && *end == '\0' && std::isfinite(value);
}

bool looksLikeOcamText(const std::string& text) {
  const auto rows = ocamTextRows(text);
  double value = 0.0;
  return !rows.empty() && !rows.front().empty() && parseNumber(rows.front().front(), value);
}

std::shared_ptr<Camera> loadOcamText(const std::string& path, const std::string& text) {
  const auto rows = ocamTextRows(text);
  const char* names[] = {"forward polynomial", "inverse polynomial", "center (row column)",
                         "affine (c d e)", "image size (height width)"};
  if (rows.size() != 5)
    throw std::runtime_error(path + ": OCamCalib calib_results.txt needs 5 lines of numbers (" +
                             "forward, inverse, center, affine, size), found " +
                             std::to_string(rows.size()));
  std::vector<std::vector<double>> values(5);
  for (std::size_t i = 0; i < 5; ++i)
    for (const std::string& token : rows[i]) {
      double v = 0.0;
      if (!parseNumber(token, v))
        throw std::runtime_error(path + ": key '" + names[i] + "': '" + token +
                                 "' is not a finite number");
      values[i].push_back(v);
    }
  const auto polynomial = [&](std::size_t i) {
    const std::vector<double>& row = values[i];
    // The count is checked against the row before it is converted (a huge count is UB to cast).
    if (row.empty() || row[0] != std::floor(row[0]) || row[0] < 2 || row[0] + 1 != static_cast<double>(row.size()))
      throw std::runtime_error(path + ": key '" + names[i] +
                               "': wrong polynomial length (the first number must be the count "
                               "of the coefficients that follow, at least 2)");
    return std::vector<double>(row.begin() + 1, row.end());
  };
  const auto expectCount = [&](std::size_t i, std::size_t n) {
    if (values[i].size() != n)
      throw std::runtime_error(path + ": key '" + names[i] + "' needs " + std::to_string(n) +
                               " numbers, found " + std::to_string(values[i].size()));
  };
  expectCount(2, 2);
  expectCount(3, 3);
  expectCount(4, 2);
  for (const double s : values[4])
    if (s <= 0.0 || s != std::floor(s) || s > 1e6)
      throw std::runtime_error(path + ": key '" + std::string(names[4]) +
                               "' must be two positive integers");
  OcamParams p;
  p.forward = polynomial(0);
  p.inverse = polynomial(1);
  p.v0 = values[2][0];
  p.u0 = values[2][1];
  p.c = values[3][0];
  p.d = values[3][1];
  p.e = values[3][2];
  p.height = static_cast<int>(values[4][0]);
  p.width = static_cast<int>(values[4][1]);
  return makeOcam(path, p);
}

// A calibration is a few hundred bytes. Reading stops one byte past the limit, so a huge file
// (a 2 GB one took 12.6 GB in yaml-cpp before std::bad_alloc) or an endless one is refused at once.
constexpr std::size_t kMaxCameraFileBytes = std::size_t{1} << 20;

std::string readText(const std::string& path) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw std::runtime_error(path + ": camera file: " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open camera file");
  std::string text(kMaxCameraFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxCameraFileBytes)
    throw std::runtime_error(path + ": larger than 1 MiB, which no calibration file is");
  return text;
}

// One entry per file format, in the order `auto` tries them. A reader gets the YAML root when
// the file parsed as a YAML map (null otherwise) and the options (the camera choice among them).
struct FileFormat {
  CameraFormat format;
  const char* signature;  // what recognises it, for the message listing the formats tried
  bool yaml;              // read from the YAML map (else from the text)
  bool manyCameras;       // takes a camera choice
  bool (*recognises)(const std::string& text, const YAML::Node* map);
  std::shared_ptr<Camera> (*read)(const std::string& path, const std::string& text, const YAML::Node* map,
                                  const CameraFileOptions& options);
  // The ids of the cameras, in file order; null for a one-camera format (its camera's id is "").
  std::vector<std::string> (*ids)(const std::string& path, const std::string& text, const YAML::Node* map);
  // The camera's frame in the rig's; null for a format without extrinsics.
  std::optional<RigidTransform> (*cameraToRig)(const std::string& path, const YAML::Node& map, const std::string& id);
};

const std::vector<FileFormat>& fileFormats() {
  using Options = CameraFileOptions;
  static const std::vector<FileFormat> formats = {
      {CameraFormat::Mdbrief, "the project's YAML (a 'model' key)", true, false,
       [](const std::string&, const YAML::Node* map) { return map && (*map)["model"]; },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options&) {
         return loadProjectYaml(path, YamlReader(path, *map));
       },
       nullptr, nullptr},
      {CameraFormat::CalibAdapter, "fisheye-calib-adapter YAML ('image' and 'parameter')", true, false,
       [](const std::string&, const YAML::Node* map) { return map && (*map)["parameter"]; },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options&) {
         return loadCalibAdapterYaml(path, YamlReader(path, *map));
       },
       nullptr, nullptr},
      {CameraFormat::Kalibr, "Kalibr camchain.yaml (camN maps with 'camera_model')", true, true,
       [](const std::string&, const YAML::Node* map) { return map && detail::isKalibrCamchain(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options& o) {
         return detail::readKalibrCamchain(path, *map, o.cameraId);
       },
       [](const std::string&, const std::string&, const YAML::Node* map) { return detail::kalibrCameraIds(*map); },
       detail::kalibrCameraToRig},
      {CameraFormat::Basalt, "basalt calib.json ('value0' with 'intrinsics')", true, true,
       [](const std::string&, const YAML::Node* map) { return map && detail::isBasaltCalibration(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options& o) {
         return detail::readBasaltCalibration(path, *map, o.cameraId);
       },
       [](const std::string& path, const std::string&, const YAML::Node* map) {
         return detail::basaltCameraIds(path, *map);
       },
       detail::basaltCameraToRig},
      {CameraFormat::OrbSlam3, "ORB-SLAM3 settings ('Camera.type')", true, true,
       [](const std::string&, const YAML::Node* map) { return map && detail::isOrbSlam3Settings(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options& o) {
         return detail::readOrbSlam3Settings(path, *map, o.cameraId);
       },
       [](const std::string&, const std::string&, const YAML::Node* map) { return detail::orbSlam3CameraIds(*map); },
       detail::orbSlam3CameraToRig},
      {CameraFormat::Euroc, "EuRoC / Kimera sensor.yaml ('sensor_type', or 'camera_model' with 'resolution')", true,
       false, [](const std::string&, const YAML::Node* map) { return map && detail::isEurocSensor(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options&) {
         return detail::readEurocSensor(path, *map);
       },
       nullptr,
       [](const std::string& path, const YAML::Node& map, const std::string&) {
         return detail::eurocCameraToRig(path, map);
       }},
      {CameraFormat::OpenCv, "OpenCV calibration YAML ('camera_matrix')", true, false,
       [](const std::string&, const YAML::Node* map) { return map && detail::isOpenCvCalibration(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options& o) {
         return detail::readOpenCvCalibration(path, *map, o);
       },
       nullptr, nullptr},
      {CameraFormat::OpenCvKd, "OpenCV FileStorage with 'K' and 'D'", true, false,
       [](const std::string&, const YAML::Node* map) { return map && detail::isOpenCvKd(*map); },
       [](const std::string& path, const std::string&, const YAML::Node* map, const Options& o) {
         return detail::readOpenCvKd(path, *map, o);
       },
       nullptr, nullptr},
      {CameraFormat::Colmap, "COLMAP cameras.txt (lines 'CAMERA_ID MODEL WIDTH HEIGHT PARAMS...')", false, true,
       [](const std::string& text, const YAML::Node*) { return detail::isColmapCameras(text); },
       [](const std::string& path, const std::string& text, const YAML::Node*, const Options& o) {
         return detail::readColmapCameras(path, text, o.cameraId);
       },
       [](const std::string& path, const std::string& text, const YAML::Node*) {
         return detail::colmapCameraIds(path, text);
       },
       nullptr},
      {CameraFormat::OcamCalib, "OCamCalib calib_results.txt (lines of numbers)", false, false,
       [](const std::string& text, const YAML::Node*) { return looksLikeOcamText(text); },
       [](const std::string& path, const std::string& text, const YAML::Node*, const Options&) {
         return loadOcamText(path, text);
       },
       nullptr, nullptr},
  };
  return formats;
}

// Turns yaml-cpp's exceptions, which do not name the file, into ours.
template <class Read>
auto namingYamlErrors(const std::string& path, Read read) {
  try {
    return read();
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": malformed camera YAML (" + e.msg + ")");
  }
}

// A calibration file's text, its YAML map (if it parsed as one) and its format.
struct RecognisedFile {
  std::string text;
  YAML::Node root;
  const YAML::Node* map = nullptr;
  const FileFormat* format = nullptr;
};

// Reads and recognises path (or takes the format chosen). The file must be of a format that
// takes a camera choice when one is given.
void recognise(const std::string& path, const CameraFileOptions& options, RecognisedFile& file) {
  file.text = readText(path);
  // Before yaml-cpp, whose own limit says only "bad file" (issue 45).
  if (const std::string nesting = internal::nestingProblem(file.text); !nesting.empty())
    throw std::runtime_error(path + ": " + nesting);
  std::string yamlError;
  try {
    file.root = YAML::Load(file.text);
  } catch (const YAML::DeepRecursion& e) {
    yamlError = "nested deeper than the parser follows (line " + std::to_string(e.mark.line + 1) + ")";
  } catch (const YAML::Exception& e) {
    yamlError = e.msg;
  }
  file.map = yamlError.empty() && file.root.IsMap() ? &file.root : nullptr;
  if (file.map) internal::requireUniqueYamlKeys(path, file.root, file.text.size());
  for (const FileFormat& format : fileFormats()) {
    const bool chosen = options.format == CameraFormat::Auto
                            ? namingYamlErrors(path, [&] { return format.recognises(file.text, file.map); })
                            : format.format == options.format;
    if (!chosen) continue;
    if (!format.manyCameras && !options.cameraId.empty())
      throw std::runtime_error(path + ": a " + toString(format.format) +
                               " file holds one camera; the camera choice '" + options.cameraId + "' does not apply");
    if (format.yaml && !file.map)
      throw std::runtime_error(path + (yamlError.empty() ? ": a " + toString(format.format) + " file is a YAML map"
                                                         : ": unparsable camera file (YAML: " + yamlError + ")"));
    file.format = &format;
    return;
  }
  // A file that did not parse is reported as such: a damaged calibration more often than an
  // unknown format.
  if (!yamlError.empty()) throw std::runtime_error(path + ": unparsable camera file (YAML: " + yamlError + ")");
  std::string tried;
  for (const FileFormat& format : fileFormats())
    tried += (tried.empty() ? "" : "; ") + toString(format.format) + ": " + format.signature;
  throw std::runtime_error(path + ": unrecognised camera file: none of the formats tried matches (" + tried +
                           "); to read it as one of them, choose the format (mdbrief --camera-format NAME, "
                           "mdbrief camera convert --format NAME; Python format=\"NAME\"; "
                           "CameraFileOptions::format)");
}

}  // namespace

namespace detail {

std::string chooseCamera(const std::string& path, const std::string& what, const std::vector<std::string>& ids,
                         const std::string& wanted) {
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ", ") + id;
  if (wanted.empty()) {
    if (ids.size() == 1) return ids.front();
    if (ids.empty()) throw std::runtime_error(path + ": " + what + " holds no camera");
    throw CameraIdRequired(path + ": " + what + " holds cameras " + list + ": choose one by its id", ids);
  }
  if (std::find(ids.begin(), ids.end(), wanted) == ids.end())
    throw std::runtime_error(path + ": " + what + " has no camera '" + wanted + "' (it has " +
                             (list.empty() ? "none" : list) + ")");
  return wanted;
}

}  // namespace detail

CameraFile readCameraFile(const std::string& path, const CameraFileOptions& options) {
  RecognisedFile file;
  recognise(path, options, file);
  const FileFormat& format = *file.format;
  return {namingYamlErrors(path, [&] { return format.read(path, file.text, file.map, options); }), format.format};
}

CameraRig readCameraRig(const std::string& path, const CameraFileOptions& options) {
  if (!options.cameraId.empty())
    throw std::invalid_argument(path + ": a rig holds all the cameras of its file; the camera choice '" +
                                options.cameraId + "' does not apply");
  RecognisedFile file;
  recognise(path, options, file);
  const FileFormat& format = *file.format;
  return namingYamlErrors(path, [&] {
    const std::vector<std::string> ids =
        format.ids ? format.ids(path, file.text, file.map) : std::vector<std::string>{""};
    if (ids.empty()) throw std::runtime_error(path + ": the " + toString(format.format) + " file holds no camera");
    std::vector<RigCamera> cameras;
    for (const std::string& id : ids) {
      CameraFileOptions one = options;
      one.cameraId = id;
      RigCamera camera{id, format.read(path, file.text, file.map, one), std::nullopt};
      if (format.cameraToRig && file.map) camera.cameraToRig = format.cameraToRig(path, *file.map, id);
      cameras.push_back(std::move(camera));
    }
    return CameraRig(path, format.format, std::move(cameras));
  });
}

std::shared_ptr<Camera> loadCamera(const std::string& path, const CameraFileOptions& options) {
  return readCameraFile(path, options).camera;
}

std::string cameraToYaml(const Camera& camera) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << camera.modelName();
  out << YAML::Key << "width" << YAML::Value << camera.imageSize().width;
  out << YAML::Key << "height" << YAML::Value << camera.imageSize().height;
  const ModelFormat* format = findModelFormat(camera.modelName());
  if (!format)
    throw std::invalid_argument("cameraToYaml: unsupported camera model '" + camera.modelName() + "'");
  format->write(camera, out);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void saveCamera(const Camera& camera, const std::string& path) {
  internal::writeFileAtomically(path, cameraToYaml(camera));
}

}  // namespace mdbrief

namespace mdbrief {

std::vector<std::string> cameraModelNames() {
  std::vector<std::string> names;
  for (const ModelFormat& f : modelFormats()) names.emplace_back(f.name);
  return names;
}

std::vector<std::string> cameraModelKeys(const std::string& model) {
  const ModelFormat* format = findModelFormat(model);
  if (!format) throw std::invalid_argument("unknown camera model '" + model + "' (known: " + modelNameList() + ")");
  return {format->keys.begin(), format->keys.end()};
}

std::shared_ptr<Camera> makeCamera(const std::string& model, cv::Size size, const CameraParameters& parameters,
                                   const std::string& source, const std::string& noun) {
  YAML::Node map(YAML::NodeType::Map);
  for (const auto& [key, value] : parameters) {
    if (const auto* number = std::get_if<double>(&value)) {
      map[key] = *number;
    } else {
      YAML::Node list(YAML::NodeType::Sequence);
      for (const double v : std::get<std::vector<double>>(value)) list.push_back(v);
      map[key] = list;
    }
  }
  const YamlReader r(source, map, "", noun);
  for (const auto& [side, value] : {std::pair<const char*, int>{"width", size.width}, {"height", size.height}})
    if (value <= 0 || value > 1000000)
      throw std::runtime_error(source + ": " + noun + " '" + side + "' must be a positive integer (got " +
                               std::to_string(value) + ")");
  return readModel(source, r, model, size.width, size.height, {});
}

CameraParameters cameraParameters(const Camera& camera) {
  const YAML::Node map = YAML::Load(cameraToYaml(camera));
  CameraParameters parameters;
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (key == "model" || key == "width" || key == "height") continue;
    if (kv.second.IsSequence())
      parameters[key] = kv.second.as<std::vector<double>>();
    else
      parameters[key] = kv.second.as<double>();
  }
  return parameters;
}

}  // namespace mdbrief
