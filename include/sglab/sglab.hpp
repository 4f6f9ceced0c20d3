// sglab/sglab.hpp — the whole runtime: SG primitives, exact closed forms,
// erf variants, hemispherical integrals, irradiance methods, registry.
#pragma once

#include "batch.hpp"
#include "branch_free.hpp"
#include "closed_forms.hpp"
#include "constants.hpp"
#include "erf.hpp"
#include "hemispherical.hpp"
#include "irradiance.hpp"
#include "math.hpp"
#include "params.hpp"
#include "registry.hpp"
#include "sg.hpp"
#include "sglab_acc.hpp"
#include "sglab_fast.hpp"
#include "sglab_lite.hpp"
#include "sglab_mid.hpp"
#include "sglab_min.hpp"
#include "sglab_tab.hpp"
