// SPDX-License-Identifier: Apache-2.0
/// @file support/TestData.h
/// @brief Paths of the sample volumes bundled in tests/data.

#pragma once

#include <string>

namespace vdbi_test {

/// Absolute path of @a name in tests/data.
std::string dataPath(const std::string& name);

} // namespace vdbi_test
