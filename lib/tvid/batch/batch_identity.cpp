#include "tvid/batch/batch_identity.hpp"


#include <nlohmann/json.hpp>

#include "tvid/io/atomic_file.hpp"
#include "tvid/io/input_file.hpp"
#include "tvid/io/sha256.hpp"
#include "tvid/io/json_file.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

nlohmann::json identity_json(const BatchIdentity& id) {
    return {{"tvid_batch", 1},
            {"experiment", id.experiment},
            {"experiment_sha256", id.experiment_sha256},
            {"overrides", id.overrides},
            {"seed", id.seed},
            {"recordings", id.recordings},
            {"data_sha256", id.data_sha256},
            {"validation", id.validation}};
}

// What differs between the directory's batch and this one, in the user's words.
std::string first_difference(const BatchIdentity& was, const BatchIdentity& now) {
    if (was.experiment_sha256 != now.experiment_sha256)
        return was.experiment == now.experiment ? "the experiment file changed since the batch began"
                                                : "it ran another experiment file (" + was.experiment + ")";
    if (was.overrides != now.overrides) {
        std::string list;
        for (const std::string& o : was.overrides) list += (list.empty() ? "" : " ") + std::string("--set ") + o;
        return "it ran with other --set overrides (" + (list.empty() ? std::string("none") : list) + ")";
    }
    if (was.seed != now.seed)
        return "it ran with " + (was.seed.empty() ? std::string("the experiment's seed") : "--seed " + was.seed);
    if (was.recordings != now.recordings) return "it ran over other recordings (--data, --data-list)";
    if (was.validation != now.validation)
        return was.validation ? "it ran with validation (without --no-validation)" : "it ran with --no-validation";
    for (std::size_t k = 0; k < was.data_sha256.size() && k < now.data_sha256.size(); ++k)
        if (was.data_sha256[k] != now.data_sha256[k])
            return "the recording " + (k < now.recordings.size() ? now.recordings[k] : std::string("of the experiment")) +
                   " changed since the batch began";
    return "its record holds no digest of the recordings (a batch of an older tvid)";
}

}  // namespace

std::vector<std::string> recording_digests(const std::vector<std::filesystem::path>& recordings) {
    std::vector<std::string> out;
    for (const std::filesystem::path& r : recordings) {
        try {
            out.push_back(sha256_of_text(read_input_file(r, "data file", kMaxRecordingBytes)));
        } catch (const InputError& e) {
            out.push_back("unreadable: " + e.problem());
        }
    }
    return out;
}

BatchIdentity batch_identity(const BatchSettings& settings, const std::vector<std::filesystem::path>& recordings,
                             const std::string& experiment_sha256, std::vector<std::string> data_sha256,
                             bool validation) {
    BatchIdentity id;
    id.experiment = settings.experiment.string();
    id.experiment_sha256 = experiment_sha256;
    for (const Override& o : settings.overrides) id.overrides.push_back(o.key + "=" + o.value);
    id.seed = settings.seed ? std::to_string(*settings.seed) : std::string();
    for (const std::filesystem::path& r : recordings) id.recordings.push_back(r.string());
    id.data_sha256 = std::move(data_sha256);
    id.validation = validation;
    return id;
}

std::filesystem::path batch_identity_file(const std::filesystem::path& dir) { return dir / ".tvid-batch.json"; }

void write_batch_identity(const std::filesystem::path& dir, const BatchIdentity& identity) {
    write_output_file(dir, batch_identity_file(dir).filename().string(), json_text(identity_json(identity)) + "\n");
}

void require_same_batch(const std::filesystem::path& dir, const BatchIdentity& identity) {
    const std::filesystem::path file = batch_identity_file(dir);
    const std::string where = (dir / "batch.csv").string();
    const std::string remedy = ": use another -o, or --force to start over";
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
        throw InputError(where, 0, "", "has no record of the batch that wrote it (" + file.filename().string() + ")" + remedy);
    BatchIdentity was;
    const nlohmann::json j = parse_json_text(read_earlier_output(file, "batch record", kMaxJsonBytes), file.string());
    try {
        was.experiment = j.at("experiment").get<std::string>();
        was.experiment_sha256 = j.at("experiment_sha256").get<std::string>();
        was.overrides = j.at("overrides").get<std::vector<std::string>>();
        was.seed = j.at("seed").get<std::string>();
        was.recordings = j.at("recordings").get<std::vector<std::string>>();
        // Absent in an older tvid's record: compared as such, it tells so.
        was.data_sha256 = j.value("data_sha256", std::vector<std::string>{});
        was.validation = j.value("validation", identity.validation);
    } catch (const nlohmann::json::exception&) {
        throw InputError(file.string(), 0, "", "is not a batch record tvid wrote" + remedy);
    }
    // A name with an invalid UTF-8 byte is stored with U+FFFD: compare as stored.
    const nlohmann::json now_stored = nlohmann::json::parse(json_text(identity_json(identity)));
    BatchIdentity now = identity;
    now.experiment = now_stored.at("experiment").get<std::string>();
    now.overrides = now_stored.at("overrides").get<std::vector<std::string>>();
    now.recordings = now_stored.at("recordings").get<std::vector<std::string>>();
    if (!(was == now)) throw InputError(where, 0, "", "is another batch's: " + first_difference(was, now) + remedy);
}

}  // namespace tvid
