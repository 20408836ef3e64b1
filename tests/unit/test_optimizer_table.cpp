// The optimizer table: one row for every OptimizerKind, found by kind and by name, and
// each row's own answers (planned iterations, a cap or not, starts.csv or not).
#include <catch2/catch.hpp>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>

#include "tvid/experiment/optimizer_settings_reader.hpp"
#include "tvid/fit/optimizer_table.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("the optimizer table has one row for every optimizer kind, in the enum's order") {
    const std::vector<OptimizerEntry>& table = optimizer_table();
    REQUIRE(table.size() == optimizer_kinds().size());
    for (std::size_t i = 0; i < table.size(); ++i) {
        CAPTURE(i);
        CHECK(table[i].kind == optimizer_kinds()[i].kind);
        CHECK(table[i].run != nullptr);
        CHECK(table[i].details != nullptr);
        CHECK(table[i].planned_iterations != nullptr);
    }
}

TEST_CASE("every optimizer is found by its kind and by its name") {
    std::set<std::string> names;
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        const OptimizerKind kind = row.kind;
        const OptimizerEntry& entry = optimizer_entry(kind);
        CHECK(entry.kind == kind);
        const std::string name = optimizer_name(kind);
        CHECK(std::string(entry.name()) == name);
        const OptimizerEntry* by_name = find_optimizer(name);
        REQUIRE(by_name != nullptr);
        CHECK(by_name->kind == kind);
        names.insert(name);
    }
    CHECK(names == std::set<std::string>{"pso", "lm", "nlopt", "pso+lm", "multistart"});
    CHECK(find_optimizer("pso_lm") == nullptr);  // the enum's spelling is not a name
    CHECK(find_optimizer("") == nullptr);
}

TEST_CASE("a kind without a row is a logic error, not a silent default") {
    CHECK_THROWS_AS(optimizer_entry(static_cast<OptimizerKind>(99)), std::logic_error);
}

TEST_CASE("each row plans its own iterations") {
    EstimationSettings s;
    s.pso.iterations = 30;
    s.lm.max_iterations = 50;
    s.nlopt.max_evaluations = 700;
    s.multistart.starts = 4;
    const auto planned = [&s](OptimizerKind kind) {
        s.optimizer = kind;
        return planned_iterations(s);
    };
    CHECK(planned(OptimizerKind::pso) == 30);
    CHECK(planned(OptimizerKind::lm) == 50);
    CHECK(planned(OptimizerKind::nlopt) == 700);
    CHECK(planned(OptimizerKind::pso_lm) == 30 + 1 + 50);  // updates, the initial swarm, the polish
    CHECK(planned(OptimizerKind::multistart) == 4 * 50);   // every start runs lm.max_iterations ...
    s.multistart.max_iterations = 7;
    CHECK(planned(OptimizerKind::multistart) == 4 * 7);    // ... unless multistart.max_iterations is given
    s.nlopt.max_evaluations = 2000000000;
    CHECK(planned(OptimizerKind::nlopt) == 1 << 30);       // an int for the progress line
}

TEST_CASE("only the swarm runs all its planned iterations, only multistart writes starts.csv") {
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        const OptimizerKind kind = row.kind;
        CAPTURE(optimizer_name(kind));
        EstimationSettings s;
        s.optimizer = kind;
        CHECK(planned_iterations_are_a_cap(s) == (kind != OptimizerKind::pso));
        CHECK((optimizer_entry(kind).starts_csv != nullptr) == (kind == OptimizerKind::multistart));
    }
}

TEST_CASE("each optimizer kind's traits are what its run does") {
    // A least-squares optimizer runs LM on the residuals (l2 only); a swarm samples the box
    // from particles; one that starts at init never samples it.
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        INFO(row.name);
        CHECK(row.summary != nullptr);
        CHECK_FALSE((row.traits.starts_at_init && (row.traits.swarm || row.traits.samples_box)));
        CHECK(row.traits.least_squares == (row.kind == OptimizerKind::lm || row.kind == OptimizerKind::pso_lm ||
                                           row.kind == OptimizerKind::multistart));
        CHECK(row.traits.swarm == (row.kind == OptimizerKind::pso || row.kind == OptimizerKind::pso_lm));
        CHECK(row.traits.samples_box == (row.kind == OptimizerKind::multistart));
        CHECK(row.traits.starts_at_init == (row.kind == OptimizerKind::lm));
        CHECK(find_optimizer_kind(row.name) == &row);
    }
    CHECK(find_optimizer_kind("pso_lm") == nullptr);
}

TEST_CASE("the settings sections under estimation: come from the kinds' own files, each with its keys") {
    CHECK(optimizer_section_keys() == std::vector<std::string>{"pso", "lm", "nlopt", "multistart"});
    // A kind's keys are its section's whole vocabulary (the reader refuses any other key).
    CHECK(std::size(PsoKind::keys) == 10);
    CHECK(std::string(LmKind::keys[5]) == "jacobian");  // read with lm:, used by every optimizer's errors
    CHECK(std::string(optimizer_kind_row(OptimizerKind::pso_lm).summary) == PsoLmKind::summary);
    CHECK(optimizer_kind_row(OptimizerKind::nlopt).check_parameters != nullptr);  // a global algorithm needs bounds
    CHECK(optimizer_kind_row(OptimizerKind::lm).check_parameters == nullptr);
}

}  // namespace TVID_UNITY_ID
