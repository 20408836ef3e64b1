// libFuzzer target: the CSV reader on arbitrary bytes. Every input must either be read or
// be refused with an InputError naming file, line and column; anything else is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tvid/io/csv_table.hpp"
#include "tvid/util/input_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("tvid-fuzz-csv-" + std::to_string(::getpid()) + ".csv");
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const tvid::CsvTable table = tvid::CsvTable::read(file);
        for (const std::string& name : table.column_names()) (void)table.column(name).size();
    } catch (const tvid::InputError&) {
        // refused with a message
    }
    return 0;
}
