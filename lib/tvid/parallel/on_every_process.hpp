#pragma once
// A step that may fail (loading the experiment, preparing the output directory) done on
// every process before they work together: when it throws on any process it throws on
// all of them, so that no process waits for one that has given up. The root rethrows its
// own error, or names the first other process that failed and its message; the other
// processes throw ProcessGroupFailure, which the front end does not print.

#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "tvid/parallel/process_group.hpp"

namespace tvid {

/// Thrown on the non-root processes when the step failed somewhere.
class ProcessGroupFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Collective: gathers every process's outcome (`failure` empty: it succeeded) and throws
/// on every process when any failed; returns when all succeeded.
void throw_if_any_failed(ProcessGroup& group, const std::exception_ptr& failure);

/// Runs `step` on every process and returns its result, or throws on every process when
/// it threw on any (throw_if_any_failed).
template <class Step>
auto on_every_process(ProcessGroup& group, Step&& step) -> decltype(step()) {
    std::exception_ptr failure;
    std::optional<decltype(step())> result;
    try {
        result.emplace(step());
    } catch (...) {
        failure = std::current_exception();
    }
    throw_if_any_failed(group, failure);
    return std::move(*result);
}

}  // namespace tvid
