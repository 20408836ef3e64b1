#pragma once
// What a batch directory's rows were computed from: the experiment file (its path and
// SHA-256), the --set overrides in order, --seed, and the recordings. Written as
// `.tvid-batch.json` when a batch starts; `--resume` continues only the same batch, so
// that one batch.csv never mixes rows of two experiments, costs, seeds or budgets.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tvid/batch/batch_job.hpp"

namespace tvid {

struct BatchIdentity {
    std::string experiment;          ///< the experiment file, as given
    std::string experiment_sha256;   ///< its content
    std::vector<std::string> overrides;  ///< "key=value", in the order given
    std::string seed;                ///< --seed, or "" for the experiment's
    std::vector<std::string> recordings; ///< --data / --data-list, in job order

    bool operator==(const BatchIdentity&) const = default;
};

/// The identity of the batch `settings` runs over `recordings`; `experiment_sha256` is the
/// digest of the experiment file as the loader read it (Experiment::config_sha256).
BatchIdentity batch_identity(const BatchSettings& settings, const std::vector<std::filesystem::path>& recordings,
                             const std::string& experiment_sha256);

/// The identity file's path in a batch directory.
std::filesystem::path batch_identity_file(const std::filesystem::path& dir);

/// Writes `identity` to the batch directory (atomically).
void write_batch_identity(const std::filesystem::path& dir, const BatchIdentity& identity);

/// For --resume: throws InputError naming the identity file and what differs (the
/// experiment file's content, --set, --seed, the recordings) unless the directory's
/// identity equals `identity`; a batch.csv without an identity file is refused too.
void require_same_batch(const std::filesystem::path& dir, const BatchIdentity& identity);

}  // namespace tvid
