#pragma once
// batch.csv: one row per job (id, status, message, the free parameters, cost, Q, fit %
// and max residual ratio on estimation and validation, evaluations, wall time, and the
// fit's verdict with its findings). Rows are
// kept as text, so a row read back for --resume is written again unchanged.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tvid {

/// Job statuses: the fit succeeded, the fit ran but did not succeed, the job's input is bad.
inline constexpr const char* kBatchOk = "ok";
inline constexpr const char* kBatchFailed = "failed";
inline constexpr const char* kBatchBadInput = "bad_input";
/// A job a stop request (Ctrl-C, SIGTERM) cut short: never written to batch.csv, so that
/// --resume runs it again.
inline constexpr const char* kBatchInterrupted = "interrupted";

bool is_batch_status(const std::string& status);

using BatchRow = std::vector<std::string>;  ///< one cell per column of the header

/// The columns of batch.csv for these free parameters and compared outputs. With one
/// output the metric columns are `q_estimation` …; with several, one set per output
/// (`q_estimation_OUT` …).
class BatchColumns {
public:
    BatchColumns(std::vector<std::string> parameters, std::vector<std::string> outputs);

    const std::vector<std::string>& header() const { return header_; }
    const std::vector<std::string>& parameters() const { return parameters_; }
    std::size_t size() const { return header_.size(); }
    /// A column name the header holds twice (a parameter named "cost" or "status"), or "".
    std::string repeated_column() const;
    /// Index of a column by name; throws std::out_of_range when absent.
    std::size_t index(const std::string& name) const;
    /// The metric column for a split ("estimation"/"validation"), a metric ("q", "fit",
    /// "max_residual_ratio_percent") and an output.
    std::string metric(const std::string& metric, const std::string& split, const std::string& output) const;

    /// A row with id, status and message and every other cell empty.
    BatchRow row(const std::string& id, const std::string& status, const std::string& message) const;

private:
    std::vector<std::string> parameters_;
    std::vector<std::string> outputs_;
    std::vector<std::string> header_;
};

/// A row as one CSV line with its newline; cells holding a comma, quote or line break
/// are quoted (RFC 4180).
std::string batch_csv_line(const BatchRow& cells);

/// A number with 17 significant digits (reads back exactly); NaN is an empty cell.
std::string batch_number(double value);

/// A cell as a number; NaN when empty or not a number.
double batch_cell_value(const std::string& cell);

struct BatchFile {
    std::vector<std::string> header;
    std::vector<BatchRow> rows;          ///< complete rows only
    std::size_t incomplete_rows = 0;     ///< torn or malformed lines that were dropped
};

/// Reads batch.csv. A row is kept when it ends with a line break and has as many cells
/// as the header; others (a line torn by an interruption) are counted and dropped.
/// Returns nothing when the file does not exist; throws std::runtime_error when it
/// cannot be read.
std::optional<BatchFile> read_batch_file(const std::filesystem::path& file);

/// Keeps batch.csv on disk as rows are added: every change rewrites the whole file
/// through write_output_file (a temporary file, synced, renamed over batch.csv), so a
/// batch killed at any moment leaves the file as it was before or after a row, never torn,
/// and keeps every job that had finished. (Rows are few; rewriting them costs nothing next
/// to a fit.)
class BatchAppender {
public:
    /// Writes `content` (the header line and any rows kept by --resume) as the file.
    BatchAppender(const std::filesystem::path& file, std::string content);
    BatchAppender(const BatchAppender&) = delete;
    BatchAppender& operator=(const BatchAppender&) = delete;
    /// Adds a row. Throws std::runtime_error naming the file when it cannot be written.
    void append(const BatchRow& row);
    /// Replaces the whole file (e.g. the rows in job order once the batch is done).
    void rewrite(std::string content);

private:
    std::filesystem::path file_;
    std::string content_;
};

}  // namespace tvid
