// libFuzzer target: the experiment loader on arbitrary YAML. Every input must either load
// or be refused with an InputError (one line naming file, line and key); anything else —
// another exception, a crash, a sanitizer report, a hang — is a finding.
//
// The YAML is written to <tmp>/configs/fuzz.yaml beside a link <tmp>/data to the
// repository's data/, so that the seed corpus (configs/*.yaml, which name ../data/...)
// reaches the CSV reading, channel binding and window checks too.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tvid/experiment/experiment.hpp"
#include "tvid/util/input_error.hpp"

namespace {

std::filesystem::path scratch_file() {
    namespace fs = std::filesystem;
    const fs::path root = fs::temp_directory_path() / ("tvid-fuzz-loader-" + std::to_string(::getpid()));
    fs::create_directories(root / "configs");
    std::error_code ec;
    fs::create_directory_symlink(fs::path(TVID_SOURCE_DIR) / "data", root / "data", ec);
    return root / "configs" / "fuzz.yaml";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path file = scratch_file();
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const tvid::Experiment ex = tvid::load_experiment(file);
        (void)ex;
    } catch (const tvid::InputError&) {
        // refused with a message: the expected answer to bad input
    }
    return 0;
}
