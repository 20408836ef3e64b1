// The process group outside mpirun (this process alone), the slices each process scores,
// and the messages between processes (string lists, the batch plan). The same code under
// `mpirun -n 2` is tested by the `mpi` ctest label (tests/mpi/).

#include <catch2/catch.hpp>

#include <numeric>

#include "tvid/batch/distributed_batch.hpp"
#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"
#include "tvid/parallel/on_every_process.hpp"
#include "tvid/parallel/process_group.hpp"
#include "tvid/parallel/string_list.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Cost = sum of the candidate's values times its position in the batch it was given, so
// a candidate scored in the wrong place or with the wrong values shows.
class PositionedSum : public CandidateEvaluator {
public:
    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override {
        ++calls;
        for (std::size_t i = 0; i < count; ++i)
            costs[i] = std::accumulate(candidates + i * dimension, candidates + (i + 1) * dimension, 0.0) *
                       static_cast<double>(i + 1);
    }
    int calls = 0;
};

}  // namespace

TEST_CASE("process slices cover every item once, in rank order, sizes within one", "[parallel]") {
    for (std::size_t count : {0, 1, 2, 7, 512, 513})
        for (int size : {1, 2, 3, 16}) {
            std::size_t next = 0, smallest = count, largest = 0;
            for (int rank = 0; rank < size; ++rank) {
                const ProcessSlice s = process_slice(count, rank, size);
                CHECK(s.begin == next);
                next = s.end;
                smallest = std::min(smallest, s.size());
                largest = std::max(largest, s.size());
            }
            CHECK(next == count);
            CHECK(largest - smallest <= 1);
        }
    CHECK(process_slice(10, 1, 3).begin == 3);
    CHECK(process_slice(10, 1, 3).end == 6);
}

TEST_CASE("a process group outside mpirun is this process alone", "[parallel]") {
    ProcessGroup alone;
    CHECK(alone.rank() == 0);
    CHECK(alone.size() == 1);
    CHECK(alone.is_root());
    std::string text = "kept";
    alone.broadcast(text);
    CHECK(text == "kept");
    CHECK(alone.gather(std::string("mine")) == std::vector<std::string>{"mine"});
    CHECK(alone.gather(std::vector<double>{1.5, 2.5}) == std::vector<double>{1.5, 2.5});
    CHECK_THROWS_AS(alone.send(1, 0, "x"), std::logic_error);
    CHECK_THROWS_AS(alone.receive(ProcessGroup::any, ProcessGroup::any), std::logic_error);
}

TEST_CASE("on_every_process alone returns the step's result or rethrows its own error", "[parallel]") {
    ProcessGroup alone;
    CHECK(on_every_process(alone, [] { return 42; }) == 42);
    // The error itself, so that bad input still prints its one line and exits 2.
    CHECK_THROWS_AS(on_every_process(alone, []() -> int { throw InputError("exp.yaml", 3, "windows", "bad"); }),
                    InputError);
    CHECK_THROWS_WITH(on_every_process(alone, []() -> int { throw InputError("exp.yaml", 3, "windows", "bad"); }),
                      "exp.yaml:3: windows: bad");
}

TEST_CASE("the distributed evaluator alone scores the whole batch with the local evaluator", "[parallel]") {
    PositionedSum local;
    ProcessGroup alone;
    for (ProcessGroup* group : {static_cast<ProcessGroup*>(nullptr), &alone}) {
        DistributedEvaluator evaluator(group, local);
        CHECK(evaluator.processes() == 1);
        const std::vector<double> candidates{1, 2, 3, 4, 5, 6};
        std::vector<double> costs(3);
        evaluator.evaluate(candidates.data(), 3, 2, costs.data());
        CHECK(costs == std::vector<double>{3, 14, 33});
    }
    CHECK(local.calls == 2);
    CandidateServers servers(alone);
    servers.release();  // nothing to release: no other process
}

TEST_CASE("a string list goes through as one message, any bytes included", "[parallel]") {
    const std::vector<std::string> items{"", "cycle-3", "a,b", "\"quoted\"", "two\nlines", "12:34", std::string(1, '\0')};
    CHECK(decode_string_list(encode_string_list(items)) == items);
    CHECK(encode_string_list({"ab", ""}) == "2:ab0:");
    CHECK(decode_string_list("").empty());
    for (const char* bad : {"3:ab", "x:ab", ":ab", "2ab", "-1:a"}) CHECK_THROWS_AS(decode_string_list(bad), std::runtime_error);
}

TEST_CASE("a batch plan goes to the other processes unchanged", "[parallel][batch]") {
    BatchPlan plan;
    plan.parameters = {"J1", "C2"};
    plan.outputs = {"omega_dw"};
    plan.jobs = {BatchJob{"run_a/cycle-3", {{"data.file", "\"/d/run a.csv\""}, {"windows.estimation", "[ { cycle: 3 } ]"}}},
                 BatchJob{"cycle-4", {}}};
    const BatchPlan back = decode_batch_plan(encode_batch_plan(plan));
    CHECK(back.parameters == plan.parameters);
    CHECK(back.outputs == plan.outputs);
    REQUIRE(back.jobs.size() == 2);
    CHECK(back.jobs[0].id == "run_a/cycle-3");
    REQUIRE(back.jobs[0].overrides.size() == 2);
    CHECK(back.jobs[0].overrides[0].key == "data.file");
    CHECK(back.jobs[0].overrides[0].value == "\"/d/run a.csv\"");
    CHECK(back.jobs[0].overrides[1].value == "[ { cycle: 3 } ]");
    CHECK(back.jobs[1].id == "cycle-4");
    CHECK(back.jobs[1].overrides.empty());
}

}  // namespace TVID_UNITY_ID
