#pragma once
// Damage in an HDF5 file that libhdf5 1.10 (Debian 12) does not survive, found before the file is
// handed to it. Written from the HDF5 file format specification, version 2.
#include <filesystem>
#include <string>

namespace mdbrief::train {

// Empty when none of the checked damage is present, else what is wrong. Checked:
// - the superblock declares 2, 4 or 8-byte offsets and lengths;
// - the free list of every local heap (signature "HEAP") ends: libhdf5 follows one that loops
//   for ever, allocating a node per step (fuzzing found a file that took 24 GB).
std::string hdf5DamageProblem(const std::filesystem::path& path);

}  // namespace mdbrief::train
