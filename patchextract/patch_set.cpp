#include "patchextract/patch_set.hpp"

#include <algorithm>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#include <hdf5.h>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "patchextract/hdf5_damage_check.hpp"

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
  // Every dataset holds numbers of at most 8 bytes or variable-length strings; a damaged type
  // could make the library's conversion buffer as large as it claims.
  Handle fileType(H5Dget_type(ds.get()), H5Tclose);
  if (!fileType.ok() || (H5Tis_variable_str(fileType.get()) <= 0 && H5Tget_size(fileType.get()) > 8))
    throw std::runtime_error(path + ": dataset /" + name + " has an unexpected element type (damaged file?)");
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0 || static_cast<size_t>(n) != expected)
    throw std::runtime_error(path + ": dataset /" + name + " has " + std::to_string(n) +
                             " elements, expected " + std::to_string(expected));
  // The writer stores every dataset contiguously inside the file; anything else is damage that
  // libhdf5 1.10 may not survive reading (fuzzing found a NULL read in H5Dread).
  Handle dcpl(H5Dget_create_plist(ds.get()), H5Pclose);
  const haddr_t offset = H5Dget_offset(ds.get());
  const double bytes = static_cast<double>(expected) * static_cast<double>(H5Tget_size(fileType.get()));
  hsize_t fileSize = 0;
  if (expected > 0 &&
      (!dcpl.ok() || H5Pget_layout(dcpl.get()) != H5D_CONTIGUOUS || offset == HADDR_UNDEF ||
       H5Fget_filesize(file, &fileSize) < 0 || static_cast<double>(H5Dget_storage_size(ds.get())) < bytes ||
       static_cast<double>(offset) + bytes > static_cast<double>(fileSize)))
    throw std::runtime_error(path + ": dataset /" + name + " is not stored as this tool writes it (damaged file?)");
  if (expected > 0 && H5Dread(ds.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    throw std::runtime_error(path + ": cannot read dataset /" + name);
}

// String lists are stored as one uint8 dataset of NUL-terminated strings: libhdf5 1.10 can loop
// forever on a damaged variable-length string heap (found by fuzzing), plain bytes it cannot.
void writeStringList(hid_t file, const char* name, const std::vector<std::string>& strings, const std::string& path) {
  std::vector<uint8_t> bytes;
  for (const auto& str : strings) {
    bytes.insert(bytes.end(), str.begin(), str.end());
    bytes.push_back(0);
  }
  writeDataset(file, name, H5T_NATIVE_UINT8, {bytes.size()}, bytes.data(), path);
}

std::vector<std::string> readStringList(hid_t file, const char* name, hsize_t count, const std::string& path) {
  {
    Handle ds(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
    Handle type(ds.ok() ? H5Dget_type(ds.get()) : -1, H5Tclose);
    if (type.ok() && H5Tis_variable_str(type.get()) > 0)
      throw std::runtime_error(path + ": dataset /" + name +
                               " is in the format of an earlier mdbrief-patchextract: extract the patches again");
  }
  std::vector<uint8_t> bytes(count);
  readDataset(file, name, H5T_NATIVE_UINT8, count, bytes.data(), path);
  if (!bytes.empty() && bytes.back() != 0)
    throw std::runtime_error(path + ": dataset /" + name + " does not end with a NUL byte (damaged file?)");
  std::vector<std::string> out;
  for (size_t start = 0; start < bytes.size();) {
    const size_t end = std::find(bytes.begin() + start, bytes.end(), uint8_t(0)) - bytes.begin();
    out.emplace_back(bytes.begin() + start, bytes.begin() + end);
    start = end + 1;
  }
  return out;
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

std::vector<std::string> PatchSet::usedImageDigests() const {
  if (imageDigests.empty()) return {};
  std::vector<std::string> used;
  for (const auto& r : records)
    if (!imageDigests[r.image].empty()) used.push_back(imageDigests[r.image]);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  return used;
}

void writePatchSet(const PatchSet& s, const fs::path& path) {
  static const QuietHdf5 quiet;
  const std::string p = path.string();
  if (s.pixels.size() != s.count() * 1024)
    throw std::runtime_error(p + ": patch pixels do not match the record count");
  if (s.counterpartPixels.size() != s.counterpartCount() * 1024)
    throw std::runtime_error(p + ": counterpart pixels do not match their count");
  // libhdf5 builds the file in memory (its core driver, no file behind it) and the image goes
  // through the checked atomic writer. Written to disk by libhdf5 itself, a failed write (a full
  // disk) left it holding a file it could not close, and the process crashed at exit.
  std::vector<char> image;
  {
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (H5Pset_fapl_core(fapl.get(), 1 << 20, false) < 0)
      throw std::runtime_error(p + ": cannot set up the in-memory HDF5 file");
    Handle file(H5Fcreate(p.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose);
    if (!file.ok()) throw std::runtime_error(p + ": cannot create the HDF5 file in memory");
    const hsize_t n = s.count();
    writeDataset(file.get(), "patches", H5T_NATIVE_UINT8, {n, 32, 32}, s.pixels.data(), p);
    writeStringList(file.get(), "images", s.images, p);
    if (!s.imageDigests.empty()) {
      if (s.imageDigests.size() != s.images.size())
        throw std::runtime_error(p + ": one image digest per image expected");
      writeStringList(file.get(), "image_digests", s.imageDigests, p);
    }
    writeDataset(file.get(), "image", H5T_NATIVE_INT32, {n}, gather(s, &PatchRecord::image).data(), p);
    writeDataset(file.get(), "x", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::x).data(), p);
    writeDataset(file.get(), "y", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::y).data(), p);
    writeDataset(file.get(), "scale", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::scale).data(), p);
    writeDataset(file.get(), "angle", H5T_NATIVE_FLOAT, {n}, gather(s, &PatchRecord::angle).data(), p);
    writeDataset(file.get(), "response", H5T_NATIVE_FLOAT, {n},
                 gather(s, &PatchRecord::response).data(), p);
    writeDataset(file.get(), "detector", H5T_NATIVE_UINT8, {n},
                 gather(s, &PatchRecord::detector).data(), p);
    if (s.counterpartCount() > 0) {
      const hsize_t q = s.counterpartCount();
      writeDataset(file.get(), "counterparts", H5T_NATIVE_UINT8, {q, 32, 32}, s.counterpartPixels.data(), p);
      writeDataset(file.get(), "counterpart_of", H5T_NATIVE_INT32, {q}, s.counterpartOf.data(), p);
    }
    writeStringAttribute(file.get(), "detectors", kDetectorNames, p);
    for (const auto& [k, v] : s.attributes) writeStringAttribute(file.get(), k, v, p);
    if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) throw std::runtime_error(p + ": flush failed");
    const ssize_t bytes = H5Fget_file_image(file.get(), nullptr, 0);
    if (bytes < 0) throw std::runtime_error(p + ": cannot get the file image");
    image.resize(static_cast<size_t>(bytes));
    if (H5Fget_file_image(file.get(), image.data(), image.size()) != bytes)
      throw std::runtime_error(p + ": cannot get the file image");
  }
  internal::writeFileAtomically(path, std::string_view(image.data(), image.size()));
}

void checkPatchSetOutput(const fs::path& path, const std::vector<fs::path>& inputs) {
  internal::checkOutputPath(path);
  internal::checkOutputsApart(inputs, {path});
}

PatchSet readPatchSet(const fs::path& path) {
  static const QuietHdf5 quiet;
  const std::string p = path.string();
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw std::runtime_error(p + ": patch file: " + problem);
  if (const std::string problem = hdf5DamageProblem(path); !problem.empty())
    throw std::runtime_error(p + ": damaged HDF5 file: " + problem);
  std::error_code ec;
  if (H5Fis_hdf5(p.c_str()) <= 0) throw std::runtime_error(p + ": not an HDF5 file");
  Handle file(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(p + ": cannot open (truncated or damaged HDF5 file?)");

  PatchSet s;
  // Sizes come from the file's header: a damaged one could claim terabytes. Nothing in the file
  // is compressed, so a dataset cannot hold more bytes than the file (64x leaves room for files
  // written by other tools with compression).
  const auto fileBytes = static_cast<double>(fs::file_size(path, ec));
  const auto plausible = [&](hsize_t count, double bytesEach, const char* name) {
    if (static_cast<double>(count) * bytesEach > 64.0 * fileBytes + 4096.0)
      throw std::runtime_error(p + ": dataset /" + name + " claims " + std::to_string(count) +
                               " elements, more than a file of " + std::to_string(static_cast<long long>(fileBytes)) +
                               " bytes can hold (damaged file?)");
    return count;
  };
  const hsize_t n = plausible(firstDimension(file.get(), "patches", 3, p), 1024, "patches");
  s.images = readStringList(file.get(), "images", plausible(firstDimension(file.get(), "images", 1, p), 1, "images"), p);
  const hsize_t m = s.images.size();
  s.pixels.resize(n * 1024);
  readDataset(file.get(), "patches", H5T_NATIVE_UINT8, n * 1024, s.pixels.data(), p);
  if (H5Lexists(file.get(), "image_digests", H5P_DEFAULT) > 0) {
    s.imageDigests = readStringList(
        file.get(), "image_digests", plausible(firstDimension(file.get(), "image_digests", 1, p), 1, "image_digests"), p);
    if (s.imageDigests.size() != m) throw std::runtime_error(p + ": /image_digests must have one entry per image");
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
  // Counterparts are optional (files of the paper's scheme have none).
  if (H5Lexists(file.get(), "counterparts", H5P_DEFAULT) > 0) {
    const hsize_t q = plausible(firstDimension(file.get(), "counterparts", 3, p), 1024, "counterparts");
    s.counterpartPixels.resize(q * 1024);
    s.counterpartOf.resize(q);
    readDataset(file.get(), "counterparts", H5T_NATIVE_UINT8, q * 1024, s.counterpartPixels.data(), p);
    readDataset(file.get(), "counterpart_of", H5T_NATIVE_INT32, q, s.counterpartOf.data(), p);
    for (hsize_t j = 0; j < q; ++j)
      if (s.counterpartOf[j] < 0 || static_cast<hsize_t>(s.counterpartOf[j]) >= n ||
          (j > 0 && s.counterpartOf[j] < s.counterpartOf[j - 1]))
        throw std::runtime_error(p + ": counterpart " + std::to_string(j) + " refers to patch " +
                                 std::to_string(s.counterpartOf[j]) +
                                 " (must be an ascending index into /patches)");
  }
  return s;
}

}  // namespace mdbrief::train
