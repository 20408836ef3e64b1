#include "tvid/analysis/determined_combinations.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace tvid {

namespace {

// Group of each index by union-find, the groups' members in order.
std::vector<std::vector<std::size_t>> linked_groups(const std::vector<std::size_t>& candidates,
                                                    const std::vector<std::vector<double>>& correlation, double correlated,
                                                    std::vector<double>& weakest) {
    std::vector<std::size_t> root(candidates.size());
    std::iota(root.begin(), root.end(), 0);
    const auto find = [&](std::size_t a) {
        while (root[a] != a) a = root[a] = root[root[a]];
        return a;
    };
    std::vector<double> link(candidates.size(), 1.0);  // the weakest link joined into each root
    for (std::size_t a = 0; a < candidates.size(); ++a)
        for (std::size_t b = a + 1; b < candidates.size(); ++b) {
            const double r = std::abs(correlation[candidates[a]][candidates[b]]);
            if (!(r >= correlated)) continue;
            const std::size_t ra = find(a), rb = find(b);
            const double weakest_link = std::min({link[ra], link[rb], r});
            if (ra != rb) root[rb] = ra;
            link[find(a)] = weakest_link;
        }
    std::vector<std::vector<std::size_t>> groups;
    weakest.clear();
    for (std::size_t a = 0; a < candidates.size(); ++a) {
        if (find(a) != a) continue;
        std::vector<std::size_t> members;
        for (std::size_t b = 0; b < candidates.size(); ++b)
            if (find(b) == a) members.push_back(candidates[b]);
        if (members.size() < 2) continue;
        groups.push_back(std::move(members));
        weakest.push_back(link[a]);
    }
    return groups;
}

}  // namespace

std::vector<DeterminedCombination> determined_combinations(const ParameterUncertainty& u,
                                                           const IdentifiabilityReport& id,
                                                           const std::vector<double>& values, double correlated) {
    std::vector<DeterminedCombination> out;
    if (!u.available || u.covariance.empty() || u.correlation.empty()) return out;
    std::vector<std::size_t> weak;
    for (std::size_t j = 0; j < id.parameters.size() && j < values.size() && j < u.std_error.size(); ++j)
        if (id.parameters[j].flag == IdentifiabilityFlag::weak && std::isfinite(u.std_error[j]) && values[j] != 0.0)
            weak.push_back(j);
    std::vector<double> weakest;
    const auto groups = linked_groups(weak, u.correlation, correlated, weakest);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const std::vector<std::size_t>& members = groups[g];
        const auto k = static_cast<Eigen::Index>(members.size());
        // The relative covariance Σ_ab / (p_a p_b): its least eigenvector is the combination
        // of relative changes the data pin best.
        Eigen::MatrixXd relative(k, k);
        for (Eigen::Index a = 0; a < k; ++a)
            for (Eigen::Index b = 0; b < k; ++b) {
                const std::size_t i = members[static_cast<std::size_t>(a)], j = members[static_cast<std::size_t>(b)];
                relative(a, b) = u.covariance[i][j] / (values[i] * values[j]);
            }
        if (!relative.allFinite()) continue;
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(relative);
        if (eig.info() != Eigen::Success) continue;
        const Eigen::VectorXd v = eig.eigenvectors().col(0);  // ascending eigenvalues
        DeterminedCombination c;
        c.members = members;
        double largest = 0.0;
        for (Eigen::Index a = 0; a < k; ++a) {
            const double w = v[a] / values[members[static_cast<std::size_t>(a)]];  // on p, not on p/|p|
            c.weights.push_back(w);
            largest = std::max(largest, std::abs(w));
        }
        // The largest weight 1, and the combination's value positive.
        double value = 0.0;
        for (Eigen::Index a = 0; a < k; ++a) value += c.weights[static_cast<std::size_t>(a)] * values[members[static_cast<std::size_t>(a)]];
        const double sign = value < 0 ? -1.0 : 1.0;
        for (double& w : c.weights) w *= sign / largest;
        c.value = 0.0;
        double variance = 0.0;
        for (std::size_t a = 0; a < members.size(); ++a) {
            c.value += c.weights[a] * values[members[a]];
            for (std::size_t b = 0; b < members.size(); ++b)
                variance += c.weights[a] * c.weights[b] * u.covariance[members[a]][members[b]];
        }
        c.std_error = std::sqrt(std::max(variance, 0.0));
        c.smallest_member_error = c.largest_member_error = id.parameters[members.front()].judged_std_error;
        for (std::size_t m : members) {
            c.smallest_member_error = std::min(c.smallest_member_error, id.parameters[m].judged_std_error);
            c.largest_member_error = std::max(c.largest_member_error, id.parameters[m].judged_std_error);
        }
        c.weakest_correlation = weakest[g];
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace tvid
