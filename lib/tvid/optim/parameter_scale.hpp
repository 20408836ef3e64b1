#pragma once
// How an optimizer moves a parameter (PEtab's parameterScale): in the parameter itself, or
// in its logarithm, so that a box of several decades is searched evenly per decade.

namespace tvid {

enum class ParameterScale { linear, log };

constexpr const char* scale_name(ParameterScale scale) { return scale == ParameterScale::log ? "log" : "linear"; }

}  // namespace tvid
