// SPDX-License-Identifier: Apache-2.0

#include "support/TestData.h"

namespace vdbi_test {

std::string
dataPath(const std::string& name)
{
    return std::string(VDBI_TEST_DATA_DIR) + "/" + name;
}

} // namespace vdbi_test
