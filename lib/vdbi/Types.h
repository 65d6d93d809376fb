// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Types.h
/// @brief Labels, label priority and the options shared by the repair stages.

#ifndef VDBI_TYPES_HAS_BEEN_INCLUDED
#define VDBI_TYPES_HAS_BEEN_INCLUDED

#include <openvdb/util/NullInterrupter.h>

#include <cstdint>
#include <unordered_map>
#include <vector>


namespace vdbi {

/// A label is the value of a voxel of an openvdb::Int32Grid.
using Label = std::int32_t;

/// @brief Which label dominates a critical element (ALGORITHM.md §2).
/// @details By default the numerically smallest label has the highest priority. A user order
/// L1, L2, ... puts those labels first, in that order; all other labels follow numerically.
class LabelPriority
{
public:
    LabelPriority() = default;
    /// @throw openvdb::ValueError if a label occurs twice in @a order.
    explicit LabelPriority(const std::vector<Label>& order);

    /// Smaller key = higher priority. Keys of distinct labels are distinct.
    std::int64_t key(Label label) const
    {
        if (!mRank.empty()) {
            const auto it = mRank.find(label);
            if (it != mRank.end()) return INT64_MIN + it->second;
        }
        return label;
    }
    /// True when @a a dominates @a b.
    bool higher(Label a, Label b) const { return key(a) < key(b); }
    /// The dominating one of two labels.
    Label pick(Label a, Label b) const { return higher(b, a) ? b : a; }

    const std::vector<Label>& order() const { return mOrder; }
    bool isDefault() const { return mOrder.empty(); }

private:
    std::vector<Label> mOrder;
    std::unordered_map<Label, std::int64_t> mRank;
};

/// @brief The user constraint "labels @c a and @c b are always separated by @c separator".
struct SeparationConstraint
{
    Label a = 0, b = 0, separator = 0;
};

/// @brief Checks a constraint set before any work: a != b, the separator differs from both,
/// and no separator of one constraint is an a or b of any constraint (such sets can contradict
/// each other, e.g. (A,B->C) with (A,C->B); ALGORITHM.md §6).
/// @throw openvdb::ValueError naming the offending constraint(s)
void validateConstraints(const std::vector<SeparationConstraint>& constraints);

/// @brief Settings of the repair stages (critical elements and fattening).
struct RepairOptions
{
    LabelPriority priority;
    /// With constraints the subdivision is 7 (ALGORITHM.md §3), else 5.
    std::vector<SeparationConstraint> constraints;
    /// Run the leaf passes with TBB; false gives the serial fallback.
    bool threaded = true;
    /// Polled between passes and per chunk of leaves; may be null.
    openvdb::util::NullInterrupter* interrupter = nullptr;
};

} // namespace vdbi

#endif // VDBI_TYPES_HAS_BEEN_INCLUDED
