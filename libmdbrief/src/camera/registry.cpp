#include "camera/registry.hpp"

namespace mdbrief::detail {

const std::vector<ModelFormat>& modelFormats() {
  // An explicit list rather than self-registering globals: the order is fixed, and a static
  // link cannot drop a model.
  static const std::vector<ModelFormat> formats = {
      pinholeModelFormat(), radialModelFormat(), ocamModelFormat(), kannalaBrandtModelFormat(),
      doubleSphereModelFormat(), ucmModelFormat(), eucmModelFormat(), radTanModelFormat(), omniModelFormat(),
  };
  return formats;
}

const ModelFormat* findModelFormat(const std::string& name) {
  for (const ModelFormat& format : modelFormats())
    if (name == format.name) return &format;
  return nullptr;
}

std::string modelNameList() {
  std::string known;
  for (const ModelFormat& f : modelFormats()) known += (known.empty() ? "" : ", ") + std::string(f.name);
  return known;
}

CameraIntrinsics readIntrinsics(const YamlReader& r, int width, int height) {
  return {width, height, r.number("fx"), r.number("fy"), r.number("cx"), r.number("cy")};
}

void emitIntrinsics(YAML::Emitter& out, const CameraIntrinsics& k) {
  emitNumbers(out, {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}});
}

void emitNumbers(YAML::Emitter& out, std::initializer_list<std::pair<const char*, double>> values) {
  for (const auto& [key, value] : values) out << YAML::Key << key << YAML::Value << value;
}

}  // namespace mdbrief::detail
