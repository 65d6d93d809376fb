// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Types.h>

#include <openvdb/Exceptions.h>

#include <sstream>
#include <string>

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

namespace {

std::string
describe(const SeparationConstraint& c)
{
    std::ostringstream os;
    os << c.a << "," << c.b << ":" << c.separator;
    return os.str();
}

} // namespace

void
validateConstraints(const std::vector<SeparationConstraint>& constraints)
{
    for (const SeparationConstraint& c : constraints) {
        if (c.a == c.b) {
            OPENVDB_THROW(openvdb::ValueError, "constraint " << describe(c)
                << ": the two separated labels must differ");
        }
        if (c.separator == c.a || c.separator == c.b) {
            OPENVDB_THROW(openvdb::ValueError, "constraint " << describe(c)
                << ": the separator must differ from the separated labels");
        }
    }
    for (const SeparationConstraint& c : constraints) {
        for (const SeparationConstraint& d : constraints) {
            if (c.separator == d.a || c.separator == d.b) {
                OPENVDB_THROW(openvdb::ValueError, "constraints " << describe(c) << " and "
                    << describe(d) << " conflict: the separator " << c.separator
                    << " of one is separated by the other (such sets can contradict each other)");
            }
        }
    }
}

} // namespace vdbi
