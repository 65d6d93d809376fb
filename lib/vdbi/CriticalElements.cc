// SPDX-License-Identifier: Apache-2.0

#include <vdbi/CriticalElements.h>
