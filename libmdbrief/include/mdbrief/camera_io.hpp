#pragma once
// Loading and saving camera calibrations. The schema of the project's YAML is documented in
// configs/cameras/README.md.
#include <memory>
#include <string>

#include "mdbrief/camera.hpp"

namespace mdbrief {

// Reads a calibration, recognising the format from the content:
//  - the project's YAML (a `model:` key; configs/cameras/README.md),
//  - OCamCalib's calib_results.txt (comment lines and five lines of numbers),
//  - fisheye-calib-adapter YAML (`image: {width, height}` and `parameter: {...}`; the model is
//    recognised from the parameter keys: coefficients -> ocam, k1..k4 -> kannala_brandt,
//    p1/p2 -> radtan, xi + alpha -> double_sphere, alpha + beta -> eucm, alpha -> ucm,
//    fx fy cx cy only -> pinhole).
// An OCam forward polynomial with a0 > 0 (z pointing forward, as in fisheye-calib-adapter) is
// negated to OCamCalib's a0 < 0; the inverse polynomial is in OCamCalib's theta convention in
// both cases (checked on the data: it vanishes at theta = -pi/2 for either file).
// Throws std::runtime_error whose message starts with the path and names the offending key
// (missing, not a number, NaN/inf, non-positive size, wrong polynomial length, unknown model or
// key, unparsable file), or says the file is over 1 MiB (refused unparsed: calibrations are a
// few hundred bytes).
std::shared_ptr<Camera> loadCamera(const std::string& path);

// The camera in the project's YAML schema (OCam: forward polynomial with a0 < 0, and the
// inverse polynomial actually used, fitted or not). Throws std::invalid_argument for a Camera
// subclass this library does not know.
std::string cameraToYaml(const Camera& camera);

// Writes cameraToYaml(camera) to path atomically (temporary file in the same directory, then
// rename). Throws std::runtime_error naming the path on failure.
void saveCamera(const Camera& camera, const std::string& path);

}  // namespace mdbrief
