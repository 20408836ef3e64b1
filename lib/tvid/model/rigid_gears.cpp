#include "tvid/model/rigid_gears.hpp"

#include "tvid/model/network_spec.hpp"

namespace tvid {

RigidGearPlan plan_rigid_gears(const NetworkSpec& spec) {
    const std::size_t n = spec.nodes.size();
    RigidGearPlan plan;
    plan.root.resize(n);
    for (std::size_t i = 0; i < n; ++i) plan.root[i] = i;
    const auto& gears = spec.ideal_gears;
    if (gears.empty()) return plan;
    std::vector<char> placed(n, 0), used(gears.size(), 0);
    for (std::size_t r = 0; r < n; ++r) {
        if (placed[r]) continue;
        placed[r] = 1;
        std::deque<std::size_t> queue{r};
        bool tied = false;
        while (!queue.empty()) {  // breadth first: parents before children
            const std::size_t at = queue.front();
            queue.pop_front();
            for (std::size_t g = 0; g < gears.size(); ++g) {
                if (used[g]) continue;
                const auto a = static_cast<std::size_t>(gears[g].a), b = static_cast<std::size_t>(gears[g].b);
                if (a != at && b != at) continue;
                const std::size_t child = a == at ? b : a;
                used[g] = 1;
                if (placed[child]) continue;  // a loop: rigid_gear_problem refuses it
                placed[child] = 1;
                plan.root[child] = r;
                plan.steps.push_back({g, child, at, child == b});
                queue.push_back(child);
                tied = true;
            }
        }
        if (tied) plan.roots.push_back(r);
    }
    return plan;
}

std::string rigid_gear_problem(const NetworkSpec& spec, std::string* element) {
    const std::size_t n = spec.nodes.size();
    // A loop: a gear whose nodes another path of gears already ties (union-find).
    std::vector<std::size_t> parent(n);
    for (std::size_t i = 0; i < n; ++i) parent[i] = i;
    const auto find = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (const IdealGearSpec& g : spec.ideal_gears) {
        const std::size_t a = find(static_cast<std::size_t>(g.a)), b = find(static_cast<std::size_t>(g.b));
        if (a == b) {
            if (element) *element = g.name;
            return "ideal gears around a loop tie nodes " + spec.nodes[static_cast<std::size_t>(g.a)].name + " and " +
                   spec.nodes[static_cast<std::size_t>(g.b)].name +
                   " twice: a rigid loop has no motion of its own (give one of its gears a stiffness: gear_mesh)";
        }
        parent[a] = b;
    }
    if (spec.ideal_gears.empty()) return "";
    std::vector<char> tied(n, 0);
    for (const IdealGearSpec& g : spec.ideal_gears) tied[static_cast<std::size_t>(g.a)] = tied[static_cast<std::size_t>(g.b)] = 1;
    const auto refuse = [&](const std::string& name, int node, const char* what) {
        if (element) *element = name;
        return std::string(what) + " on node " + spec.nodes[static_cast<std::size_t>(node)].name +
               ", which an ideal_gear ties rigidly to another node: not supported; join them by a gear_mesh instead";
    };
    for (const SpeedSourceSpec& s : spec.speed_sources)
        if (tied[static_cast<std::size_t>(s.node)]) return refuse(s.name, s.node, "a speed source prescribes the speed");
    for (const CylinderSpec& c : spec.cylinders)
        if (tied[static_cast<std::size_t>(c.node)])
            return refuse(c.name, c.node, "a cylinder adds its angle-dependent inertia");
    return "";
}

}  // namespace tvid
