#pragma once
// A dataset for other tools (`sva export`): CSV with one row per reading, and ASCII PLY of the contact points
// with their outward normals, coloured by object (docs/dataset-format.md, "Exports"). Both are written atomically.
#include <sva/dataset.hpp>

#include <cstddef>
#include <filesystem>
#include <string>

namespace sva::io {

// object,object_name,status,iterations,px,py,pz,nx,ny,nz,xx,xy,xz,p_r0c0,...: ground truth first, then the reading.
void write_dataset_csv(const Dataset& data, const std::filesystem::path& file);
// The readings with contact; `source` names the dataset in the header's comment. Returns the points written.
std::size_t write_dataset_ply(const Dataset& data, const std::string& source, const std::filesystem::path& file);

// The contact sheet of `sva simulate --preview`: per reading, the tactile image beside the object's contact
// locations, this reading's highlighted (at most `max_readings`).
void write_preview(const Dataset& data, const std::filesystem::path& png, int max_readings = 48);

}  // namespace sva::io
