#pragma once
// The optimizer kinds an experiment can name, one row each (after pagmo2's problem that
// describes itself): experiment/optimizer_kinds/NAME.hpp declares the kind's name, a
// one-line summary, its traits and, when it has a settings section of its own under
// `estimation:`, that section's settings type, keys and reader (which validates them), and
// any check of the parameters beyond its traits. OptimizerKind, the rows of
// experiment/optimizer_kinds.hpp, the fields of EstimationSettings, the reader of
// `estimation:` and the fit floor's table of runs (fit/optimizer_table.cpp:
// `OptimizerEntry kind_optimizer()`, defined in fit/optimizers/kind_run.cpp) all walk
// these rows; nothing else names an optimizer.
//
// Adding an optimizer: its NAME.hpp here, its row below (and in the sections, if it has
// one), and its run, lib/tvid/fit/optimizers/NAME_run.cpp.

#include "tvid/experiment/optimizer_kinds/lm.hpp"
#include "tvid/experiment/optimizer_kinds/multistart.hpp"
#include "tvid/experiment/optimizer_kinds/nlopt.hpp"
#include "tvid/experiment/optimizer_kinds/pso.hpp"
#include "tvid/experiment/optimizer_kinds/pso_lm.hpp"

//     X(kind,       Kind)         the order of OptimizerKind, the help and the reports
#define TVID_OPTIMIZER_KINDS(X) \
    X(pso, PsoKind)             \
    X(lm, LmKind)               \
    X(nlopt, NloptKind)         \
    X(pso_lm, PsoLmKind)        \
    X(multistart, MultistartKind)

//     X(section,    Kind)         a settings section under `estimation:`, one field of EstimationSettings
#define TVID_OPTIMIZER_SECTIONS(X) \
    X(pso, PsoKind)                \
    X(lm, LmKind)                  \
    X(nlopt, NloptKind)            \
    X(multistart, MultistartKind)
