#pragma once
// A table of numeric measurement channels read from a CSV file: one header row of
// column names, then one row of numbers per sample. Lines starting with '#' and blank
// lines are skipped. A UTF-8 byte-order mark is accepted.

#include <cstddef>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

namespace tvid {

class CsvTable {
public:
    /// Reads and validates the whole file. Throws InputError naming the file, the line
    /// and the column for: a missing file, an empty file, no header, an empty or
    /// duplicate column name, a non-numeric cell, NaN or inf, a short or long row,
    /// a file with no data rows, and a ';' or tab separated file (the message says the
    /// separator must be ',').
    static CsvTable read(const std::filesystem::path& file);
    /// A table made in memory from named columns of equal length (several recordings laid
    /// end to end, experiment/recording_join.hpp). `file` names it; it has no digest and no
    /// lines of its own (line_of_row gives 0: unknown).
    static CsvTable from_columns(std::filesystem::path file, std::vector<std::string> names,
                                 std::vector<std::vector<double>> columns);

    const std::filesystem::path& file() const { return file_; }
    /// SHA-256 (hex) of the bytes this table was read from, hashed as they were read.
    const std::string& content_sha256() const { return content_sha256_; }
    const std::vector<std::string>& column_names() const { return names_; }
    std::size_t rows() const { return rows_; }
    bool has_column(const std::string& name) const;
    /// Values of one column, one per data row. Throws std::out_of_range if absent.
    const std::vector<double>& column(const std::string& name) const;
    /// The 1-based line number in the file of data row `row` (0-based), for messages; 0
    /// for a table made in memory.
    int line_of_row(std::size_t row) const { return row_lines_.empty() ? 0 : row_lines_.at(row); }
    /// The 1-based line number of the header row.
    int header_line() const { return header_line_; }

    /// Checks that `name` holds strictly increasing values; otherwise throws InputError
    /// naming the first offending line and the column.
    void require_strictly_increasing(const std::string& name) const;

private:
    std::filesystem::path file_;
    std::string content_sha256_;
    std::vector<std::string> names_;
    std::unordered_map<std::string, std::size_t> column_index_;  ///< name -> position in names_
    std::vector<std::vector<double>> columns_;
    std::vector<int> row_lines_;
    std::size_t rows_ = 0;
    int header_line_ = 0;
};

}  // namespace tvid
