// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Interruption.h
/// @brief Polls the user's interrupter between passes and per chunk of leaves, never per voxel.

#ifndef VDBI_INTERRUPTION_HAS_BEEN_INCLUDED
#define VDBI_INTERRUPTION_HAS_BEEN_INCLUDED

#include <vdbi/Exceptions.h>

#include <openvdb/util/NullInterrupter.h>

#include <atomic>
#include <string>

namespace vdbi {

/// Shared by the tasks of one pass: once interrupted, the remaining chunks return at once.
class InterruptFlag
{
public:
    explicit InterruptFlag(openvdb::util::NullInterrupter* interrupter)
        : mInterrupter(interrupter) {}

    /// Call once per chunk; true means: stop this chunk.
    bool poll()
    {
        if (mStopped.load(std::memory_order_relaxed)) return true;
        if (mInterrupter && mInterrupter->wasInterrupted()) {
            mStopped.store(true, std::memory_order_relaxed);
            return true;
        }
        return false;
    }

    /// Call after the pass: throws if any chunk saw the request.
    /// @throw vdbi::Interrupted
    void throwIfStopped(const char* stage) const
    {
        if (mStopped.load()) throw Interrupted(std::string("interrupted during ") + stage);
    }

private:
    openvdb::util::NullInterrupter* mInterrupter;
    std::atomic<bool> mStopped{false};
};

/// Polls between passes. @throw vdbi::Interrupted
inline void
checkInterrupt(openvdb::util::NullInterrupter* interrupter, const char* stage)
{
    if (interrupter && interrupter->wasInterrupted()) {
        throw Interrupted(std::string("interrupted before ") + stage);
    }
}

} // namespace vdbi

#endif // VDBI_INTERRUPTION_HAS_BEEN_INCLUDED
