#include "tvid/parallel/on_every_process.hpp"

namespace tvid {

namespace {

// "1" + the message when the step failed, "0" when it succeeded.
std::string outcome(const std::exception_ptr& failure) {
    if (!failure) return "0";
    try {
        std::rethrow_exception(failure);
    } catch (const std::exception& e) {
        return std::string("1") + e.what();
    } catch (...) {
        return "1unknown error";
    }
}

}  // namespace

void throw_if_any_failed(ProcessGroup& group, const std::exception_ptr& failure) {
    if (group.size() == 1) {
        if (failure) std::rethrow_exception(failure);
        return;
    }
    // The root collects every outcome and broadcasts its verdict: "" all succeeded, or
    // the message of the first process (by rank) that failed.
    const std::vector<std::string> outcomes = group.gather(outcome(failure));
    std::string verdict;
    for (std::size_t r = 0; r < outcomes.size() && verdict.empty(); ++r)
        if (outcomes[r][0] == '1') verdict = "process " + std::to_string(r) + ": " + outcomes[r].substr(1);
    group.broadcast(verdict);
    if (verdict.empty()) return;
    if (!group.is_root()) throw ProcessGroupFailure(verdict);
    if (failure) std::rethrow_exception(failure);
    throw std::runtime_error(verdict);
}

}  // namespace tvid
