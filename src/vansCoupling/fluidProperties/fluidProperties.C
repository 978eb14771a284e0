// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluidProperties.H"

namespace Foam
{
    defineTypeNameAndDebug(fluidProperties, 0);
}
