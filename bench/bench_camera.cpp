// ns per pixelToBearing / bearingToPixel call for each camera model, on the shipped
// calibrations (configs/cameras) and synthetic ones for the models without a shipped file.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/radtan.hpp"
#include "mdbrief/camera/unified.hpp"

namespace {

std::shared_ptr<mdbrief::Camera> benchCamera(const std::string& name) {
  if (name == "eucm")
    return std::make_shared<mdbrief::UnifiedCamera>(
        mdbrief::UnifiedParams{{752, 480, 460.9, 459.6, 365.8, 248.9}, 0.586, 1.139});
  if (name == "radtan")
    return std::make_shared<mdbrief::RadTanCamera>(
        mdbrief::RadTanParams{{752, 480, 459.3, 457.8, 366.0, 248.3}, -0.29, 0.08, 3e-4, -2e-5});
  return mdbrief::loadCamera(std::string(MDBRIEF_SOURCE_DIR) + "/configs/cameras/" + name + ".yaml");
}

// Valid pixels on a coarse grid, and their bearings, as the work items.
struct Samples {
  std::vector<cv::Point2d> pixels;
  std::vector<cv::Vec3d> bearings;
};

Samples makeSamples(const mdbrief::Camera& camera) {
  Samples s;
  const cv::Size size = camera.imageSize();
  for (double v = 0; v < size.height; v += 7.3)
    for (double u = 0; u < size.width; u += 7.9) {
      cv::Vec3d b;
      if (camera.isValid({u, v}) && camera.pixelToBearing({u, v}, b)) {
        s.pixels.emplace_back(u, v);
        s.bearings.push_back(b);
      }
    }
  return s;
}

void BM_PixelToBearing(benchmark::State& state, const std::string& name) {
  const auto camera = benchCamera(name);
  const Samples s = makeSamples(*camera);
  std::size_t i = 0;
  cv::Vec3d b;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera->pixelToBearing(s.pixels[i], b));
    benchmark::DoNotOptimize(b);
    if (++i == s.pixels.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_BearingToPixel(benchmark::State& state, const std::string& name) {
  const auto camera = benchCamera(name);
  const Samples s = makeSamples(*camera);
  std::size_t i = 0;
  cv::Point2d p;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera->bearingToPixel(s.bearings[i], p));
    benchmark::DoNotOptimize(p);
    if (++i == s.bearings.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

#define MDBRIEF_CAMERA_BENCH(name)                                              \
  BENCHMARK_CAPTURE(BM_PixelToBearing, name, std::string(#name));               \
  BENCHMARK_CAPTURE(BM_BearingToPixel, name, std::string(#name))

MDBRIEF_CAMERA_BENCH(pinhole_example);
MDBRIEF_CAMERA_BENCH(radial_example);
MDBRIEF_CAMERA_BENCH(lafida_fisheye0);
MDBRIEF_CAMERA_BENCH(kannala_brandt_example);
MDBRIEF_CAMERA_BENCH(double_sphere_example);
MDBRIEF_CAMERA_BENCH(eucm);
MDBRIEF_CAMERA_BENCH(radtan);

}  // namespace
