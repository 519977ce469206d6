// COLMAP's cameras.txt: comment lines (#) and one line per camera, "CAMERA_ID MODEL WIDTH HEIGHT
// PARAMS[]", chosen by its CAMERA_ID. The models SIMPLE_PINHOLE (f cx cy), PINHOLE (fx fy cx cy),
// SIMPLE_RADIAL (f cx cy k), RADIAL (f cx cy k1 k2), OPENCV (fx fy cx cy k1 k2 p1 p2),
// FULL_OPENCV (fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6) and OPENCV_FISHEYE (fx fy cx cy k1 k2 k3 k4)
// are read. COLMAP puts the centre of the top-left pixel at (0.5, 0.5), OpenCV (and this
// library) at (0, 0): the principal point moves by 0.5 px along both axes.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/radtan.hpp"

namespace mdbrief::detail {
namespace {

constexpr double kPixelCentreShift = 0.5;

struct Line {
  int number;  // 1-based, for messages
  std::vector<std::string> tokens;
};

std::vector<Line> dataLines(const std::string& text) {
  std::vector<Line> lines;
  // A UTF-8 byte order mark, which the YAML formats accept, is no data.
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream tokens(line);
    Line l{number, {}};
    for (std::string t; tokens >> t;) l.tokens.push_back(t);
    lines.push_back(l);
  }
  return lines;
}

bool isCameraId(const std::string& token) {
  if (token.empty() || token.size() > 10) return false;
  for (const unsigned char c : token)
    if (!std::isdigit(c)) return false;
  return true;
}

// The shape of a COLMAP line's first two tokens, looser than what reads: a signed integer and a
// word of any case, so that a negative CAMERA_ID or a lower-case model is reported as the COLMAP
// error it is, not as a file of another format (issue 29).
bool looksLikeCameraId(const std::string& token) {
  const std::size_t sign = !token.empty() && (token[0] == '-' || token[0] == '+');
  return token.size() > sign && isCameraId(token.substr(sign));
}

bool looksLikeModelName(const std::string& token) {
  if (token.empty() || !std::isalpha(static_cast<unsigned char>(token[0]))) return false;
  for (const unsigned char c : token)
    if (!std::isalnum(c) && c != '_') return false;
  return true;
}

struct ColmapModel {
  const char* name;
  const char* layout;  // the parameters, for messages
  std::size_t count;
  bool oneFocal;  // f for both axes
};

const ColmapModel kModels[] = {
    {"SIMPLE_PINHOLE", "f cx cy", 3, true},
    {"PINHOLE", "fx fy cx cy", 4, false},
    {"SIMPLE_RADIAL", "f cx cy k", 4, true},
    {"RADIAL", "f cx cy k1 k2", 5, true},
    {"OPENCV", "fx fy cx cy k1 k2 p1 p2", 8, false},
    {"FULL_OPENCV", "fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6", 12, false},
    {"OPENCV_FISHEYE", "fx fy cx cy k1 k2 k3 k4", 8, false},
};

}  // namespace

bool isColmapCameras(const std::string& text) {
  const std::vector<Line> lines = dataLines(text);
  return !lines.empty() && lines.front().tokens.size() >= 4 && looksLikeCameraId(lines.front().tokens[0]) &&
         looksLikeModelName(lines.front().tokens[1]);
}

std::vector<std::string> colmapCameraIds(const std::string& path, const std::string& text) {
  const std::vector<Line> lines = dataLines(text);
  std::vector<std::string> ids;
  for (const Line& l : lines) {
    if (l.tokens.size() < 4 || !looksLikeCameraId(l.tokens[0]) || !looksLikeModelName(l.tokens[1]))
      throw std::runtime_error(path + ": line " + std::to_string(l.number) +
                               " is not 'CAMERA_ID MODEL WIDTH HEIGHT PARAMS...'");
    if (!isCameraId(l.tokens[0]))
      throw std::runtime_error(path + ": line " + std::to_string(l.number) + ": CAMERA_ID " + l.tokens[0] +
                               " must be a non-negative integer");
    const std::string id = std::to_string(std::strtoull(l.tokens[0].c_str(), nullptr, 10));
    // Two cameras of one id: which is meant cannot be told (the first was taken silently).
    if (const auto same = std::find(ids.begin(), ids.end(), id); same != ids.end())
      throw std::runtime_error(path + ": CAMERA_ID " + id + " appears twice, on lines " +
                               std::to_string(lines[static_cast<std::size_t>(same - ids.begin())].number) + " and " +
                               std::to_string(l.number));
    ids.push_back(id);
  }
  return ids;
}

std::shared_ptr<Camera> readColmapCameras(const std::string& path, const std::string& text, const std::string& camera) {
  const std::vector<Line> lines = dataLines(text);
  const std::vector<std::string> ids = colmapCameraIds(path, text);
  const std::string id = chooseCamera(path, "the COLMAP cameras file", ids, camera);
  const Line& line = lines[std::find(ids.begin(), ids.end(), id) - ids.begin()];
  const std::string where = path + ": line " + std::to_string(line.number) + " (camera " + id + ")";
  const std::string& name = line.tokens[1];
  const ColmapModel* model = nullptr;
  for (const ColmapModel& m : kModels)
    if (name == m.name) model = &m;
  if (!model) {
    std::string known;
    for (const ColmapModel& m : kModels) known += (known.empty() ? "" : ", ") + std::string(m.name);
    std::string upper = name;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const bool caseOnly = upper != name && std::any_of(std::begin(kModels), std::end(kModels),
                                                       [&](const ColmapModel& m) { return upper == m.name; });
    throw std::runtime_error(where + ": model " + name + " has no camera model here (supported: " + known + ")" +
                             (caseOnly ? "; COLMAP's model names are upper case: " + upper : ""));
  }
  std::vector<double> values;
  for (std::size_t i = 2; i < line.tokens.size(); ++i) {
    char* end = nullptr;
    const double v = std::strtod(line.tokens[i].c_str(), &end);
    if (end == line.tokens[i].c_str() || *end != '\0' || !std::isfinite(v))
      throw std::runtime_error(where + ": '" + line.tokens[i] + "' is not a finite number");
    values.push_back(v);
  }
  for (std::size_t i = 0; i < 2; ++i)
    if (values[i] <= 0.0 || values[i] != std::floor(values[i]) || values[i] > 1e6)
      throw std::runtime_error(where + ": WIDTH and HEIGHT must be positive integers");
  if (values.size() - 2 != model->count)
    throw std::runtime_error(where + ": " + name + " needs " + std::to_string(model->count) + " parameters (" +
                             model->layout + "), found " + std::to_string(values.size() - 2));
  const int width = static_cast<int>(values[0]), height = static_cast<int>(values[1]);
  const double* p = values.data() + 2;
  const std::size_t centre = model->oneFocal ? 1 : 2;
  const CameraIntrinsics k{width, height, p[0], model->oneFocal ? p[0] : p[1], p[centre] - kPixelCentreShift,
                           p[centre + 1] - kPixelCentreShift};
  const double* d = p + centre + 2;  // the distortion coefficients
  if (name == "SIMPLE_PINHOLE" || name == "PINHOLE") return construct<PinholeCamera>(path, k);
  if (name == "SIMPLE_RADIAL") return construct<RadTanCamera>(path, RadTanParams{k, d[0]});
  if (name == "RADIAL") return construct<RadTanCamera>(path, RadTanParams{k, d[0], d[1]});
  if (name == "OPENCV") return construct<RadTanCamera>(path, RadTanParams{k, d[0], d[1], d[2], d[3]});
  if (name == "OPENCV_FISHEYE")
    return construct<KannalaBrandtCamera>(path, KannalaBrandtParams{k, d[0], d[1], d[2], d[3]});
  RadTanParams full{k, d[0], d[1], d[2], d[3], d[4]};  // FULL_OPENCV
  full.k4 = d[5];
  full.k5 = d[6];
  full.k6 = d[7];
  return construct<RadTanCamera>(path, full);
}

}  // namespace mdbrief::detail
