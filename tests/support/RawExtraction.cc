// SPDX-License-Identifier: Apache-2.0

#include "support/RawExtraction.h"

namespace vdbi_test {

vdbi::Result
extractRaw(const openvdb::Int32Grid& grid, vdbi::Options options)
{
    options.remesh = false;
    return vdbi::extractInterfaces(grid, options);
}

} // namespace vdbi_test
