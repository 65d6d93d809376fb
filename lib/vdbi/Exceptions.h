// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/Exceptions.h
/// @brief The library's own exceptions. Bad input raises OpenVDB's (TypeError, ValueError,
/// IoError); these are for broken postconditions and interruption.

#ifndef VDBI_EXCEPTIONS_HAS_BEEN_INCLUDED
#define VDBI_EXCEPTIONS_HAS_BEEN_INCLUDED

#include <stdexcept>

namespace vdbi {

/// A guarantee of the method failed (a complex edge in a patch, a critical element left).
/// Seeing one is a bug in the library.
class TopologyError : public std::logic_error
{
public:
    using std::logic_error::logic_error;
};

/// The interrupter given in the options asked to stop.
class Interrupted : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

} // namespace vdbi

#endif // VDBI_EXCEPTIONS_HAS_BEEN_INCLUDED
