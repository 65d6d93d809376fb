// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Interfaces.h>
