#pragma once
// Every optimizer's settings and their one check, for the experiment reader: each options
// header declares `validate(const XSettings&)` (the first problem found, as the key at
// fault and what is wrong with it: settings_problem.hpp), and each optimizer's own file
// defines it.

#include "tvid/optim/lm_options.hpp"
#include "tvid/optim/multistart_options.hpp"
#include "tvid/optim/nlopt_options.hpp"
#include "tvid/optim/pso_options.hpp"
#include "tvid/optim/settings_problem.hpp"
