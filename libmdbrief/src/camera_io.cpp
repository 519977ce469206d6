#include "mdbrief/camera_io.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mdbrief/camera_double_sphere.hpp"
#include "mdbrief/camera_kannala_brandt.hpp"
#include "mdbrief/camera_ocam.hpp"
#include "mdbrief/camera_pinhole.hpp"
#include "mdbrief/camera_radial.hpp"
#include "mdbrief/camera_radtan.hpp"
#include "mdbrief/camera_unified.hpp"
#include "mdbrief/internal/atomic_file.hpp"
#include "mdbrief/internal/input_file.hpp"

namespace mdbrief {
namespace {

// Reads typed values out of one YAML map, with errors "<file>: key '<prefix><key>' ...".
class YamlReader {
 public:
  YamlReader(std::string path, YAML::Node map, std::string prefix = "")
      : path_(std::move(path)), map_(std::move(map)), prefix_(std::move(prefix)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::runtime_error(path_ + ": key '" + prefix_ + key + "' " + what);
  }

  bool has(const std::string& key) const { return static_cast<bool>(map_[key]); }

  YAML::Node node(const std::string& key) const {
    const YAML::Node n = map_[key];
    if (!n) fail(key, "is missing");
    return n;
  }

  double number(const std::string& key) const {
    const YAML::Node n = node(key);
    double value = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, value)) fail(key, "is not a number");
    if (!std::isfinite(value)) fail(key, "is NaN or infinite");
    return value;
  }

  double number(const std::string& key, double fallback) const {
    return has(key) ? number(key) : fallback;
  }

  int size(const std::string& key) const {
    const double value = number(key);
    if (value <= 0.0 || value != std::floor(value) || value > 1e6)
      fail(key, "must be a positive integer (got " + node(key).Scalar() + ")");
    return static_cast<int>(value);
  }

  std::vector<double> numbers(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsSequence()) fail(key, "must be a list of numbers");
    std::vector<double> values;
    for (std::size_t i = 0; i < n.size(); ++i) {
      double value = 0.0;
      if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], value))
        fail(key, "element " + std::to_string(i) + " is not a number");
      if (!std::isfinite(value)) fail(key, "element " + std::to_string(i) + " is NaN or infinite");
      values.push_back(value);
    }
    return values;
  }

  YamlReader sub(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsMap()) fail(key, "must be a map");
    return {path_, n, prefix_ + key + "."};
  }

  std::set<std::string> keys() const {
    std::set<std::string> result;
    for (const auto& kv : map_) result.insert(kv.first.as<std::string>());
    return result;
  }

  // Rejects keys outside `allowed` so that typos do not silently fall back to defaults.
  void requireOnly(const std::set<std::string>& allowed, const std::string& model) const {
    for (const std::string& key : keys())
      if (!allowed.count(key)) fail(key, "is not part of the '" + model + "' schema");
  }

 private:
  std::string path_;
  YAML::Node map_;
  std::string prefix_;
};

// The model's parameters as "key: value, ..." (its YAML form without the image size), for
// errors about the model as a whole.
std::string parameterList(const Camera& camera) {
  std::istringstream yaml(cameraToYaml(camera));
  std::string line, list;
  while (std::getline(yaml, line))
    if (line.rfind("model:", 0) != 0 && line.rfind("width:", 0) != 0 && line.rfind("height:", 0) != 0)
      list += (list.empty() ? "" : ", ") + line;
  return list;
}

// A calibration can parse and still be no lens: checked along 16 rays from the principal point
// to the image border, over the pixels the model calls valid, the angle to the optical axis
// must grow with the distance (the distortion is monotonic over the field of view), every
// pixel must unproject and project back within 0.01 px (the inverse converges), and the image
// must span at least half a degree. Throws std::runtime_error naming the file, the parameters
// and the failing pixel.
void requirePlausible(const Camera& camera, const std::string& path) {
  const auto fail = [&](const std::string& problem) {
    return std::runtime_error(path + ": " + camera.modelName() + " camera with " + parameterList(camera) + ": " +
                              problem);
  };
  cv::Point2d centre;
  if (!camera.bearingToPixel({0, 0, 1}, centre) || !camera.isValid(centre))
    throw fail("the optical axis does not project into the image");
  const cv::Size size = camera.imageSize();
  double widest = 0.0;
  for (int k = 0; k < 16; ++k) {
    const cv::Point2d dir(std::cos(k * CV_PI / 8), std::sin(k * CV_PI / 8));
    double previous = -1.0;
    for (double r = 1.0; r < size.width + size.height; r += 1.0) {
      const cv::Point2d px = centre + r * dir;
      if (!camera.isValid(px)) break;
      cv::Vec3d b;
      cv::Point2d back;
      if (!camera.pixelToBearing(px, b) || !camera.bearingToPixel(b, back) || !(cv::norm(back - px) < 0.01))
        throw fail("the inverse does not converge at pixel (" + std::to_string(px.x) + ", " + std::to_string(px.y) + ")");
      const double angle = std::atan2(std::hypot(b[0], b[1]), b[2]);
      if (!(angle > previous))
        throw fail("the distortion is not monotonic: the ray angle stops growing at pixel (" + std::to_string(px.x) +
                   ", " + std::to_string(px.y) + ")");
      previous = angle;
      widest = std::max(widest, angle);
    }
  }
  if (!(widest * 180.0 / CV_PI >= 0.5))
    throw fail("the image spans only " + std::to_string(widest * 180.0 / CV_PI) + " degrees from the axis");
}

// Builds a camera, turning the constructors' std::invalid_argument into a runtime_error that
// names the file (the constructors already name the parameter), and checks that it is a lens.
template <class CameraType, class Params>
std::shared_ptr<Camera> construct(const std::string& path, const Params& params) {
  std::shared_ptr<Camera> camera;
  try {
    camera = std::make_shared<CameraType>(params);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  requirePlausible(*camera, path);
  return camera;
}

// a0 > 0 means z points forward (fisheye-calib-adapter); OCamCalib's convention is a0 < 0.
std::shared_ptr<Camera> makeOcam(const std::string& path, OcamParams p) {
  if (!p.forward.empty() && p.forward.front() > 0.0)
    for (double& a : p.forward) a = -a;
  return construct<OcamCamera>(path, p);
}

CameraIntrinsics readIntrinsics(const YamlReader& r, int width, int height) {
  return {width, height, r.number("fx"), r.number("fy"), r.number("cx"), r.number("cy")};
}

// Writers get the camera as the model's class (a model name another class claims is unsupported).
template <class CameraType>
const CameraType& as(const Camera& camera) {
  if (const auto* c = dynamic_cast<const CameraType*>(&camera)) return *c;
  throw std::invalid_argument("cameraToYaml: unsupported camera model '" + camera.modelName() + "'");
}

void emitIntrinsics(YAML::Emitter& out, const CameraIntrinsics& k) {
  out << YAML::Key << "fx" << YAML::Value << k.fx << YAML::Key << "fy" << YAML::Value << k.fy
      << YAML::Key << "cx" << YAML::Value << k.cx << YAML::Key << "cy" << YAML::Value << k.cy;
}

void emitList(YAML::Emitter& out, const char* key, const std::vector<double>& values) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const double v : values) out << v;
  out << YAML::EndSeq;
}

// One registration per camera model: its name in the project YAML, its keys there (besides
// model, width and height), how they are read and written (in this order, the file format),
// and the distortion keys (besides fx fy cx cy, same names) that name it in a
// fisheye-calib-adapter file. Adding a model is adding an entry.
struct ModelFormat {
  const char* name;
  std::set<std::string> keys;
  std::shared_ptr<Camera> (*read)(const std::string& path, const YamlReader& r, int width, int height);
  void (*write)(const Camera& camera, YAML::Emitter& out);
  std::vector<std::set<std::string>> adapterKeys;
};

// The order is the one error messages list the models in.
const std::vector<ModelFormat>& modelFormats() {
  static const std::vector<ModelFormat> formats = {
      {"pinhole", {"fx", "fy", "cx", "cy"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         return construct<PinholeCamera>(path, readIntrinsics(r, width, height));
       },
       [](const Camera& camera, YAML::Emitter& out) { emitIntrinsics(out, as<PinholeCamera>(camera).intrinsics()); },
       {std::set<std::string>{}}},  // fx fy cx cy only
      {"radial", {"fx", "fy", "cx", "cy", "xi", "unit_px"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         RadialParams p;
         p.intrinsics = readIntrinsics(r, width, height);
         p.xi = r.number("xi");
         p.unitPx = r.number("unit_px", p.unitPx);
         return construct<RadialCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const RadialParams& p = as<RadialCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "xi" << YAML::Value << p.xi;
         out << YAML::Key << "unit_px" << YAML::Value << p.unitPx;
       },
       {}},
      {"ocam", {"forward", "inverse", "c", "d", "e", "u0", "v0", "valid_radius"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         OcamParams p;
         p.width = width;
         p.height = height;
         p.forward = r.numbers("forward");
         if (r.has("inverse")) p.inverse = r.numbers("inverse");
         p.c = r.number("c");
         p.d = r.number("d");
         p.e = r.number("e");
         p.u0 = r.number("u0");
         p.v0 = r.number("v0");
         p.validRadius = r.number("valid_radius", 0.0);
         return makeOcam(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const OcamParams& p = as<OcamCamera>(camera).params();
         emitList(out, "forward", p.forward);
         emitList(out, "inverse", p.inverse);
         out << YAML::Key << "c" << YAML::Value << p.c << YAML::Key << "d" << YAML::Value << p.d
             << YAML::Key << "e" << YAML::Value << p.e << YAML::Key << "u0" << YAML::Value << p.u0
             << YAML::Key << "v0" << YAML::Value << p.v0;
         if (p.validRadius > 0.0) out << YAML::Key << "valid_radius" << YAML::Value << p.validRadius;
       },
       {}},  // the adapter writes OCam in a layout of its own (loadCalibAdapterYaml)
      {"kannala_brandt", {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         const KannalaBrandtParams p{readIntrinsics(r, width, height), r.number("k1"), r.number("k2"),
                                     r.number("k3"), r.number("k4")};
         return construct<KannalaBrandtCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const KannalaBrandtParams& p = as<KannalaBrandtCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "k1" << YAML::Value << p.k1 << YAML::Key << "k2" << YAML::Value << p.k2
             << YAML::Key << "k3" << YAML::Value << p.k3 << YAML::Key << "k4" << YAML::Value << p.k4;
       },
       {{"k1", "k2", "k3", "k4"}}},
      {"double_sphere", {"fx", "fy", "cx", "cy", "xi", "alpha"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         const DoubleSphereParams p{readIntrinsics(r, width, height), r.number("xi"), r.number("alpha")};
         return construct<DoubleSphereCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const DoubleSphereParams& p = as<DoubleSphereCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "xi" << YAML::Value << p.xi;
         out << YAML::Key << "alpha" << YAML::Value << p.alpha;
       },
       {{"xi", "alpha"}}},
      {"ucm", {"fx", "fy", "cx", "cy", "alpha"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         const UnifiedParams p{readIntrinsics(r, width, height), r.number("alpha"), 1.0};
         return construct<UnifiedCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const UnifiedParams& p = as<UnifiedCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "alpha" << YAML::Value << p.alpha;
       },
       {{"alpha"}}},
      {"eucm", {"fx", "fy", "cx", "cy", "alpha", "beta"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         const UnifiedParams p{readIntrinsics(r, width, height), r.number("alpha"), r.number("beta")};
         return construct<UnifiedCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const UnifiedParams& p = as<UnifiedCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "alpha" << YAML::Value << p.alpha;
         out << YAML::Key << "beta" << YAML::Value << p.beta;
       },
       {{"alpha", "beta"}}},
      {"radtan", {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"},
       [](const std::string& path, const YamlReader& r, int width, int height) {
         const RadTanParams p{readIntrinsics(r, width, height), r.number("k1"), r.number("k2"),
                              r.number("p1"), r.number("p2"), r.number("k3", 0.0)};
         return construct<RadTanCamera>(path, p);
       },
       [](const Camera& camera, YAML::Emitter& out) {
         const RadTanParams& p = as<RadTanCamera>(camera).params();
         emitIntrinsics(out, p.intrinsics);
         out << YAML::Key << "k1" << YAML::Value << p.k1 << YAML::Key << "k2" << YAML::Value << p.k2
             << YAML::Key << "p1" << YAML::Value << p.p1 << YAML::Key << "p2" << YAML::Value << p.p2
             << YAML::Key << "k3" << YAML::Value << p.k3;
       },
       {{"k1", "k2", "p1", "p2"}, {"k1", "k2", "k3", "p1", "p2"}}},
  };
  return formats;
}

const ModelFormat* findFormat(const std::string& name) {
  for (const ModelFormat& format : modelFormats())
    if (name == format.name) return &format;
  return nullptr;
}

std::shared_ptr<Camera> loadProjectYaml(const std::string& path, const YamlReader& r) {
  const YAML::Node modelNode = r.node("model");
  if (!modelNode.IsScalar()) r.fail("model", "must be a model name");
  const std::string model = modelNode.Scalar();
  const int width = r.size("width"), height = r.size("height");
  const ModelFormat* format = findFormat(model);
  if (!format) {
    std::string known;
    for (const ModelFormat& f : modelFormats()) known += (known.empty() ? "" : ", ") + std::string(f.name);
    r.fail("model", "names an unknown model '" + model + "' (known: " + known + ")");
  }
  std::set<std::string> allowed = format->keys;
  allowed.insert({"model", "width", "height"});
  r.requireOnly(allowed, model);
  return format->read(path, r, width, height);
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
  readIntrinsics(r, width, height);  // a missing or bad fx fy cx cy is reported first
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

}  // namespace

std::shared_ptr<Camera> loadCamera(const std::string& path) {
  const std::string text = readText(path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    if (looksLikeOcamText(text)) return loadOcamText(path, text);
    throw std::runtime_error(path + ": unparsable camera file (YAML: " + e.msg + ")");
  }
  try {
    if (root.IsMap()) {
      const YamlReader reader(path, root);
      if (reader.has("model")) return loadProjectYaml(path, reader);
      if (reader.has("parameter")) return loadCalibAdapterYaml(path, reader);
      throw std::runtime_error(path + ": key 'model' is missing (and no 'parameter' key of a "
                               "fisheye-calib-adapter file either)");
    }
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": malformed camera YAML (" + e.msg + ")");
  }
  if (looksLikeOcamText(text)) return loadOcamText(path, text);
  throw std::runtime_error(path + ": unrecognised camera file (neither YAML with a 'model' key "
                           "nor an OCamCalib calib_results.txt)");
}

std::string cameraToYaml(const Camera& camera) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << camera.modelName();
  out << YAML::Key << "width" << YAML::Value << camera.imageSize().width;
  out << YAML::Key << "height" << YAML::Value << camera.imageSize().height;
  const ModelFormat* format = findFormat(camera.modelName());
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
