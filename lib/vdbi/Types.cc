// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Types.h>

#include <openvdb/Exceptions.h>

namespace vdbi {

LabelPriority::LabelPriority(const std::vector<Label>& order)
    : mOrder(order)
{
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (!mRank.emplace(order[i], std::int64_t(i)).second) {
            OPENVDB_THROW(openvdb::ValueError, "label " << order[i]
                << " occurs twice in the priority order");
        }
    }
}

} // namespace vdbi
