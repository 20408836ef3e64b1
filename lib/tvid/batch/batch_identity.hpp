#pragma once
// What a batch directory's rows were computed from: the experiment file (its path and
// SHA-256), the --set overrides in order, --seed, --no-validation, and the recordings
// (their paths and the SHA-256 of their content, so that a recording edited since is
// seen). Written as
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
    /// The SHA-256 of each recording's content, in job order; with no recordings (cycles of
    /// the experiment's own data file), that file's. A recording that cannot be read has
    /// "unreadable: WHY" (its job's row says why).
    std::vector<std::string> data_sha256;
    bool validation = true;              ///< false: --no-validation

    bool operator==(const BatchIdentity&) const = default;
};

/// The identity of the batch `settings` runs over `recordings`; `experiment_sha256` is the
/// digest of the experiment file as the loader read it (Experiment::config_sha256),
/// `data_sha256` the digests of the recordings (recording_digests), `validation` false
/// under --no-validation.
BatchIdentity batch_identity(const BatchSettings& settings, const std::vector<std::filesystem::path>& recordings,
                             const std::string& experiment_sha256, std::vector<std::string> data_sha256,
                             bool validation);

/// The SHA-256 of each recording's content (each read once, whole, as the loader reads
/// it); "unreadable: WHY" for one that cannot be read.
std::vector<std::string> recording_digests(const std::vector<std::filesystem::path>& recordings);

/// The identity file's path in a batch directory.
std::filesystem::path batch_identity_file(const std::filesystem::path& dir);

/// Writes `identity` to the batch directory (atomically).
void write_batch_identity(const std::filesystem::path& dir, const BatchIdentity& identity);

/// For --resume: throws InputError naming the identity file and what differs (the
/// experiment file's content, --set, --seed, --no-validation, the recordings or their
/// content) unless the directory's
/// identity equals `identity`; a batch.csv without an identity file is refused too.
void require_same_batch(const std::filesystem::path& dir, const BatchIdentity& identity);

}  // namespace tvid
