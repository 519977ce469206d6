#include "poster_dev.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/unique_keys.hpp"
#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The value at `key` of `node` as T; throws naming the file and the key when missing or of
// another type.
template <typename T>
T field(const json& node, const char* key, const std::string& file) {
  const auto it = node.find(key);
  if (it == node.end()) throw std::runtime_error(file + ": missing \"" + key + "\"");
  try {
    return it->get<T>();
  } catch (const json::exception&) {
    throw std::runtime_error(file + ": \"" + key + "\" has the wrong type");
  }
}

cv::Matx33d matrix3(const json& node, const std::string& file, int frame) {
  const auto rows = field<std::vector<std::vector<double>>>(node, "G", file);
  cv::Matx33d g;
  if (rows.size() != 3) throw std::runtime_error(file + ": frame " + std::to_string(frame) + ": G is not 3x3");
  for (int r = 0; r < 3; ++r) {
    if (rows[r].size() != 3) throw std::runtime_error(file + ": frame " + std::to_string(frame) + ": G is not 3x3");
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(rows[r][c]))
        throw std::runtime_error(file + ": frame " + std::to_string(frame) + ": G has a non-finite entry");
      g(r, c) = rows[r][c];
    }
  }
  if (!(std::abs(cv::determinant(g)) > 0.0))
    throw std::runtime_error(file + ": frame " + std::to_string(frame) + ": G is singular");
  return g;
}

// A file of the data set as 8-bit grey of the calibration's size.
cv::Mat readGrey(const fs::path& path, cv::Size size, const char* what) {
  cv::Mat image = loadEvaluationImage(path.string());
  if (image.size() != size)
    throw std::runtime_error(path.string() + ": the " + what + " is " + internal::sizeText(image.size()) +
                             " but the calibration " + internal::sizeText(size));
  return image;
}

double incidenceDeg(const cv::Vec3d& ray) { return std::acos(ray[2] / cv::norm(ray)) * 180.0 / CV_PI; }

bool inside(const cv::Mat& mask, const cv::Point2d& p) {
  if (!(p.x >= 0 && p.y >= 0 && p.x <= mask.cols - 1 && p.y <= mask.rows - 1)) return false;
  return mask.at<uchar>(cvRound(p.y), cvRound(p.x)) != 0;
}

}  // namespace

std::optional<cv::Point2d> PosterDev::map(int a, int b, const cv::Point2d& pixel) const {
  const PosterFrame& fa = frames[a];
  const PosterFrame& fb = frames[b];
  if (!inside(fa.mask, pixel)) return std::nullopt;
  cv::Vec3d ray;
  if (!camera->pixelToBearing(pixel, ray) || incidenceDeg(ray) > maxIncidenceDeg) return std::nullopt;
  const cv::Vec3d q = fa.gInverse * ray;
  if (!(q[2] > 0)) return std::nullopt;  // behind the poster's plane as seen from frame a
  const cv::Point2d pattern(q[0] / q[2], q[1] / q[2]);
  if (!(pattern.x >= printed.x && pattern.x <= printed.x + printed.width && pattern.y >= printed.y &&
        pattern.y <= printed.y + printed.height))
    return std::nullopt;
  const cv::Vec3d rb = fb.g * cv::Vec3d(pattern.x, pattern.y, 1.0);
  cv::Point2d out;
  if (!(rb[2] > 0) || incidenceDeg(rb) > maxIncidenceDeg || !camera->bearingToPixel(rb, out) || !inside(fb.mask, out))
    return std::nullopt;
  return out;
}

PosterDev loadPosterDev(const std::string& dir) {
  const fs::path root(dir);
  const std::string gtPath = (root / "ground_truth.json").string();
  if (!fs::is_regular_file(gtPath)) throw std::runtime_error(gtPath + ": no such file");
  json gt;
  {
    std::ifstream in(gtPath, std::ios::binary);
    if (!in) throw std::runtime_error(gtPath + ": cannot read");
    try {
      gt = internal::parseJsonUniqueKeys<json>(in);
    } catch (const json::exception&) {
      throw std::runtime_error(gtPath + ": not a JSON object");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(gtPath + ": " + e.what());
    }
    if (!gt.is_object()) throw std::runtime_error(gtPath + ": not a JSON object");
  }
  PosterDev p;
  const std::string calibration = (root / field<std::string>(gt, "calibration", gtPath)).string();
  try {
    p.camera = loadCamera(calibration);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(calibration + ": " + e.what());
  }
  const json region = field<json>(gt, "printed_region_pattern_px", gtPath);
  const double x0 = field<double>(region, "x0", gtPath), x1 = field<double>(region, "x1", gtPath);
  const double y0 = field<double>(region, "y0", gtPath), y1 = field<double>(region, "y1", gtPath);
  if (!(x1 > x0 && y1 > y0)) throw std::runtime_error(gtPath + ": printed_region_pattern_px is empty");
  p.printed = cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
  p.maxIncidenceDeg = field<double>(gt, "max_incidence_deg", gtPath);
  if (!(p.maxIncidenceDeg > 0 && p.maxIncidenceDeg < 180))
    throw std::runtime_error(gtPath + ": max_incidence_deg must be in (0, 180)");
  const auto frames = field<json>(gt, "frames", gtPath);
  if (!frames.is_array() || frames.size() < 2) throw std::runtime_error(gtPath + ": \"frames\" needs at least two frames");
  for (const auto& f : frames) {
    PosterFrame frame;
    frame.id = field<int>(f, "frame", gtPath);
    frame.g = matrix3(f, gtPath, frame.id);
    frame.gInverse = frame.g.inv();
    frame.path = (root / field<std::string>(f, "image", gtPath)).string();
    frame.image = readGrey(frame.path, p.camera->imageSize(), "frame");
    frame.mask = readGrey(root / field<std::string>(f, "mask", gtPath), p.camera->imageSize(), "mask");
    p.frames.push_back(std::move(frame));
  }
  return p;
}

EvalSequence posterDevSequence(const PosterDev& poster) {
  EvalSequence s;
  s.name = "poster-dev";
  s.camera = poster.camera;
  s.cameraIsModel = true;
  s.baseline = true;
  for (const auto& f : poster.frames) {
    s.images.push_back(f.image);
    s.regions.push_back(f.mask);
  }
  const auto shared = std::make_shared<const PosterDev>(poster);
  const int n = static_cast<int>(poster.frames.size());
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      s.pairs.push_back({a, b, [shared, a, b](const cv::Point2d& px) { return shared->map(a, b, px); }});
  return s;
}

}  // namespace mdbrief::eval
