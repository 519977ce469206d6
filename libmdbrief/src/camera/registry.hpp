#pragma once
// The camera models of the project's YAML (configs/cameras/README.md): one registration per
// model, defined next to the model (at the end of camera/<model>.cpp), and the one list of them
// (camera/registry.cpp) that camera/io.cpp reads and writes by. Adding a model is writing
// its registration and adding it to that list.
#include <initializer_list>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/intrinsics.hpp"

namespace mdbrief::detail {

// A model's entry: its name in the project YAML, its keys there (besides model, width and
// height), how they are read and written (in this order, the file format), and the distortion
// keys (besides fx fy cx cy, same names) that name it in a fisheye-calib-adapter file.
struct ModelFormat {
  const char* name;
  std::set<std::string> keys;
  // Errors start with `source` (the file, or the Python constructor).
  std::shared_ptr<Camera> (*read)(const std::string& source, const YamlReader& r, int width, int height);
  void (*write)(const Camera& camera, YAML::Emitter& out);
  std::vector<std::set<std::string>> adapterKeys;
};

// The registrations, each in its model's source.
ModelFormat pinholeModelFormat();
ModelFormat radialModelFormat();
ModelFormat ocamModelFormat();
ModelFormat kannalaBrandtModelFormat();
ModelFormat doubleSphereModelFormat();
ModelFormat ucmModelFormat();
ModelFormat eucmModelFormat();
ModelFormat radTanModelFormat();
ModelFormat omniModelFormat();

// Every model, in the order error messages list them.
const std::vector<ModelFormat>& modelFormats();
// The model called `name`, or null.
const ModelFormat* findModelFormat(const std::string& name);
// "pinhole, radial, ...": the model names for messages.
std::string modelNameList();

// Helpers of the registrations.
CameraIntrinsics readIntrinsics(const YamlReader& r, int width, int height);
void emitIntrinsics(YAML::Emitter& out, const CameraIntrinsics& k);
void emitNumbers(YAML::Emitter& out, std::initializer_list<std::pair<const char*, double>> values);

// Writers get the camera as the model's class (a model name another class claims is unsupported).
template <class CameraType>
const CameraType& as(const Camera& camera) {
  if (const auto* c = dynamic_cast<const CameraType*>(&camera)) return *c;
  throw std::invalid_argument("cameraToYaml: unsupported camera model '" + camera.modelName() + "'");
}

}  // namespace mdbrief::detail
