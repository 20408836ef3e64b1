#include "tvid/batch/batch_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "tvid/io/csv_field.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/input_file.hpp"

namespace tvid {

namespace {

constexpr const char* kMetrics[] = {"q", "fit", "max_residual_ratio_percent"};
constexpr const char* kSplits[] = {"estimation", "validation"};

}  // namespace

bool is_batch_status(const std::string& status) {
    return status == kBatchOk || status == kBatchFailed || status == kBatchBadInput;
}

BatchColumns::BatchColumns(std::vector<std::string> parameters, std::vector<std::string> outputs)
    : parameters_(std::move(parameters)), outputs_(std::move(outputs)) {
    header_ = {"id", "status", "message"};
    header_.insert(header_.end(), parameters_.begin(), parameters_.end());
    header_.push_back("cost");
    for (const char* split : kSplits)
        for (const std::string& out : outputs_)
            for (const char* m : kMetrics) header_.push_back(metric(m, split, out));
    header_.push_back("evaluations");
    header_.push_back("verdict");   // "clean", or "1 error, 2 warnings"
    header_.push_back("findings");  // "error:residuals_not_white(Tds);warning:at_bound(C21)"
    header_.push_back("wall_seconds");  // last: the one cell that differs between equal runs
}

std::string BatchColumns::repeated_column() const {
    for (std::size_t i = 0; i < header_.size(); ++i)
        if (std::find(header_.begin() + static_cast<std::ptrdiff_t>(i) + 1, header_.end(), header_[i]) != header_.end())
            return header_[i];
    return {};
}

std::size_t BatchColumns::index(const std::string& name) const {
    const auto it = std::find(header_.begin(), header_.end(), name);
    if (it == header_.end()) throw std::out_of_range("batch.csv has no column " + name);
    return static_cast<std::size_t>(it - header_.begin());
}

std::string BatchColumns::metric(const std::string& metric, const std::string& split, const std::string& output) const {
    return metric + "_" + split + (outputs_.size() > 1 ? "_" + output : "");
}

BatchRow BatchColumns::row(const std::string& id, const std::string& status, const std::string& message) const {
    BatchRow r(header_.size());
    r[0] = id;
    r[1] = status;
    r[2] = message;
    return r;
}

std::string batch_csv_line(const BatchRow& cells) {
    std::string line;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (i) line += ',';
        line += csv_field(cells[i]);
    }
    return line + '\n';
}

std::string batch_number(double value) {
    if (std::isnan(value)) return "";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", value);
    return buf;
}

double batch_cell_value(const std::string& cell) {
    if (cell.empty()) return std::numeric_limits<double>::quiet_NaN();
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    return end == cell.c_str() + cell.size() ? v : std::numeric_limits<double>::quiet_NaN();
}

std::optional<BatchFile> read_batch_file(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return std::nullopt;
    const std::string text = read_earlier_output(file, "batch table", kMaxRecordingBytes);

    // RFC 4180 records: a record ends at a line break outside quotes.
    BatchFile out;
    BatchRow record(1);
    bool quoted = false, header_done = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                record.back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                record.back() += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            record.emplace_back();
        } else if (c == '\n') {
            if (!record.empty() && !record.back().empty() && record.back().back() == '\r') record.back().pop_back();
            if (!header_done) {
                out.header = record;
                header_done = true;
            } else if (record.size() == out.header.size()) {
                out.rows.push_back(record);
            } else {
                ++out.incomplete_rows;
            }
            record.assign(1, "");
        } else {
            record.back() += c;
        }
    }
    if (record.size() > 1 || !record.front().empty()) ++out.incomplete_rows;  // no final line break: torn
    return out;
}

BatchAppender::BatchAppender(const std::filesystem::path& file, std::string content) : file_(file) {
    rewrite(std::move(content));
}

void BatchAppender::append(const BatchRow& row) {
    rewrite(content_ + batch_csv_line(row));
}

void BatchAppender::rewrite(std::string content) {
    write_named_output_file(file_, content);
    content_ = std::move(content);
}

}  // namespace tvid
