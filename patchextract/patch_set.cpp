#include "patchextract/patch_set.hpp"

#include <stdexcept>
#include <system_error>

#include <hdf5.h>
#include <unistd.h>

namespace mdbrief::train {

namespace fs = std::filesystem;

namespace {

constexpr const char* kDetectorNames = "orb,akaze,surf";

// Closes an HDF5 handle at scope exit.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle& operator=(Handle&&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Silences libhdf5's error printing: problems are reported by exceptions instead.
struct QuietHdf5 {
  QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};

Handle stringType() {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

void writeDataset(hid_t file, const char* name, hid_t type, const std::vector<hsize_t>& dims,
                  const void* data, const std::string& path) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl.get(), false);  // no timestamps: reproducible files
  Handle ds(H5Dcreate2(file, name, type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
            H5Dclose);
  if (!ds.ok() || H5Dwrite(ds.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error(path + ": cannot write dataset /" + name);
}

void writeStringAttribute(hid_t file, const std::string& key, const std::string& value,
                          const std::string& path) {
  const Handle type = stringType();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(file, key.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  const char* p = value.c_str();
  if (!attr.ok() || H5Awrite(attr.get(), type.get(), &p) < 0)
    throw std::runtime_error(path + ": cannot write attribute " + key);
}

template <class T>
std::vector<T> gather(const PatchSet& s, T PatchRecord::*field) {
  std::vector<T> v;
  v.reserve(s.count());
  for (const auto& r : s.records) v.push_back(r.*field);
  return v;
}

// Reads a 1-D (or N x 32 x 32 for patches) dataset, checking its element count.
void readDataset(hid_t file, const char* name, hid_t memType, size_t expected, void* out,
                 const std::string& path) {
  Handle ds(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!ds.ok()) throw std::runtime_error(path + ": missing dataset /" + name);
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0 || static_cast<size_t>(n) != expected)
    throw std::runtime_error(path + ": dataset /" + name + " has " + std::to_string(n) +
                             " elements, expected " + std::to_string(expected));
  if (expected > 0 && H5Dread(ds.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    throw std::runtime_error(path + ": cannot read dataset /" + name);
}

hsize_t firstDimension(hid_t file, const char* name, int rank, const std::string& path) {
  Handle ds(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!ds.ok()) throw std::runtime_error(path + ": missing dataset /" + name);
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  hsize_t dims[3] = {0, 0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != rank)
    throw std::runtime_error(path + ": dataset /" + name + " must have rank " +
                             std::to_string(rank));
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (rank == 3 && (dims[1] != 32 || dims[2] != 32))
    throw std::runtime_error(path + ": dataset /" + name + " must be N x 32 x 32");
  return dims[0];
}

}  // namespace

void writePatchSet(const PatchSet& s, const fs::path& path) {
  static const QuietHdf5 quiet;
  const std::string p = path.string();
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(p + ": output folder " + dir.string() + " does not exist");
  if (s.pixels.size() != s.count() * 1024)
    throw std::runtime_error(p + ": patch pixels do not match the record count");
  const fs::path tmp = dir / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT), H5Fclose);
    if (!file.ok()) throw std::runtime_error(p + ": cannot create " + tmp.string());
    const hsize_t n = s.count();
    writeDataset(file.get(), "patches", H5T_NATIVE_UINT8, {n, 32, 32}, s.pixels.data(), p);
    std::vector<const char*> names;
    for (const auto& im : s.images) names.push_back(im.c_str());
    const Handle strType = stringType();
    writeDataset(file.get(), "images", strType.get(), {names.size()}, names.data(), p);
    writeDataset(file.get(), "image", H5T_NATIVE_INT32, {n}, gather(s, &PatchRecord::image).data(), p);
    writeDataset(file.get(), "x", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::x).data(), p);
    writeDataset(file.get(), "y", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::y).data(), p);
    writeDataset(file.get(), "scale", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::scale).data(), p);
    writeDataset(file.get(), "angle", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::angle).data(), p);
    writeDataset(file.get(), "response", H5T_NATIVE_FLOAT, {n},
                 gather(s, &PatchRecord::response).data(), p);
    writeDataset(file.get(), "detector", H5T_NATIVE_UINT8, {n},
                 gather(s, &PatchRecord::detector).data(), p);
    writeStringAttribute(file.get(), "detectors", kDetectorNames, p);
    for (const auto& [k, v] : s.attributes) writeStringAttribute(file.get(), k, v, p);
    if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) throw std::runtime_error(p + ": flush failed");
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error(p + ": cannot replace: " + ec.message());
  }
}

PatchSet readPatchSet(const fs::path& path) {
  static const QuietHdf5 quiet;
  const std::string p = path.string();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw std::runtime_error(p + ": no such patch file");
  if (H5Fis_hdf5(p.c_str()) <= 0) throw std::runtime_error(p + ": not an HDF5 file");
  Handle file(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(p + ": cannot open (truncated or damaged HDF5 file?)");

  PatchSet s;
  const hsize_t n = firstDimension(file.get(), "patches", 3, p);
  const hsize_t m = firstDimension(file.get(), "images", 1, p);
  s.pixels.resize(n * 1024);
  readDataset(file.get(), "patches", H5T_NATIVE_UINT8, n * 1024, s.pixels.data(), p);
  {
    const Handle strType = stringType();
    std::vector<char*> names(m, nullptr);
    readDataset(file.get(), "images", strType.get(), m, names.data(), p);
    for (char* name : names) s.images.emplace_back(name ? name : "");
    Handle ds(H5Dopen2(file.get(), "images", H5P_DEFAULT), H5Dclose);
    Handle space(H5Dget_space(ds.get()), H5Sclose);
    if (m > 0) H5Dvlen_reclaim(strType.get(), space.get(), H5P_DEFAULT, names.data());
  }
  s.records.resize(n);
  std::vector<int32_t> image(n);
  std::vector<float> x(n), y(n), scale(n), angle(n), response(n);
  std::vector<uint8_t> detector(n);
  readDataset(file.get(), "image", H5T_NATIVE_INT32, n, image.data(), p);
  readDataset(file.get(), "x", H5T_NATIVE_FLOAT, n, x.data(), p);
  readDataset(file.get(), "y", H5T_NATIVE_FLOAT, n, y.data(), p);
  readDataset(file.get(), "scale", H5T_NATIVE_FLOAT, n, scale.data(), p);
  readDataset(file.get(), "angle", H5T_NATIVE_FLOAT, n, angle.data(), p);
  readDataset(file.get(), "response", H5T_NATIVE_FLOAT, n, response.data(), p);
  readDataset(file.get(), "detector", H5T_NATIVE_UINT8, n, detector.data(), p);
  for (hsize_t i = 0; i < n; ++i) {
    if (image[i] < 0 || static_cast<hsize_t>(image[i]) >= m)
      throw std::runtime_error(p + ": patch " + std::to_string(i) + " has image index " +
                               std::to_string(image[i]) + " outside the image list");
    s.records[i] = {image[i], x[i], y[i], scale[i], angle[i], response[i], detector[i]};
  }
  return s;
}

}  // namespace mdbrief::train
