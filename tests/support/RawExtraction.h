// SPDX-License-Identifier: Apache-2.0
/// @file support/RawExtraction.h
/// @brief The pipeline with remeshing off, which most tests check exactly.

#pragma once

#include <vdbi/Interfaces.h>

namespace vdbi_test {

/// vdbi::extractInterfaces() with Options::remesh off: the raw extraction, the voxel faces
/// themselves. The other settings of @a options are kept.
vdbi::Result extractRaw(const openvdb::Int32Grid& grid, vdbi::Options options = vdbi::Options());

} // namespace vdbi_test
