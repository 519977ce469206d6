// The include paths of 0.1 (mdbrief/camera_io.hpp, ...) still compile against an installed
// mdbrief and reach the grouped headers: each names the type its header declares, and one call
// goes through them. Exit 0 when the call works.
#include <cstdio>

#include <mdbrief/bow_vector.hpp>
#include <mdbrief/camera.hpp>
#include <mdbrief/camera_double_sphere.hpp>
#include <mdbrief/camera_intrinsics.hpp>
#include <mdbrief/camera_io.hpp>
#include <mdbrief/camera_kannala_brandt.hpp>
#include <mdbrief/camera_ocam.hpp>
#include <mdbrief/camera_omni.hpp>
#include <mdbrief/camera_pinhole.hpp>
#include <mdbrief/camera_radial.hpp>
#include <mdbrief/camera_radtan.hpp>
#include <mdbrief/camera_unified.hpp>
#include <mdbrief/camera_with_intrinsics.hpp>
#include <mdbrief/database.hpp>
#include <mdbrief/descriptor.hpp>
#include <mdbrief/detector.hpp>
#include <mdbrief/guided_matcher.hpp>
#include <mdbrief/hamming.hpp>
#include <mdbrief/image_pyramid.hpp>
#include <mdbrief/masked_hamming.hpp>
#include <mdbrief/matcher.hpp>
#include <mdbrief/patterns.hpp>
#include <mdbrief/tangent_plane.hpp>
#include <mdbrief/test_set.hpp>
#include <mdbrief/vocabulary.hpp>
#include <mdbrief/vocabulary_text.hpp>

static_assert(sizeof(mdbrief::CameraIntrinsics) > 0 && sizeof(mdbrief::DetectorOptions) > 0 &&
              sizeof(mdbrief::DescriptorOptions) > 0 && sizeof(mdbrief::MatchOptions) > 0 &&
              sizeof(mdbrief::GuidedMatchOptions) > 0 && sizeof(mdbrief::Database) > 0);

int main(int argc, char** argv) {
  if (argc < 2) return 1;
  const auto camera = mdbrief::loadCamera(argv[1]);
  std::printf("old include paths: %s loads as %s\n", argv[1], camera->modelName().c_str());
  return camera->imageSize().width > 0 ? 0 : 1;
}
