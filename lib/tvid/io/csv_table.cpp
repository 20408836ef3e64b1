#include "tvid/io/csv_table.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <ios>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "tvid/io/input_file.hpp"
#include "tvid/io/sha256.hpp"
#include "tvid/util/input_error.hpp"

// Reading strategy: the whole file is read into one string, then walked line by line
// with std::string_view; cells are parsed in place with std::from_chars, so the only
// per-file allocations are the column vectors (reserved up front) and the names.

namespace tvid {

namespace {

using std::string_view;

constexpr std::size_t kMaxShownChars = 40;  // a bad cell is quoted in messages up to this length

constexpr const char* kSeparatorAdvice =
    " — tvid reads comma-separated files (',' between columns, '.' as decimal point)";

/// Blank characters trimmed around names and cells ('\r' covers stray carriage returns).
bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r';
}

string_view trim(string_view s) {
    std::size_t b = 0;
    std::size_t e = s.size();
    while (b < e && is_blank(s[b])) ++b;
    while (e > b && is_blank(s[e - 1])) --e;
    return s.substr(b, e - b);
}

/// Removes one pair of double quotes around `s` (already trimmed), trimming inside.
string_view unquote(string_view s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return trim(s.substr(1, s.size() - 2));
    return s;
}

/// `s` for a message, shortened (at a UTF-8 character boundary) if very long.
std::string shown(string_view s) {
    if (s.size() <= kMaxShownChars) return std::string(s);
    std::size_t cut = kMaxShownChars;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0U) == 0x80U) --cut;
    return std::string(s.substr(0, cut)) + "...";
}

std::string plural(std::size_t n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

std::string format_double(double x) {
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, res.ptr);
}

std::string separator_error_text(char sep) {
    return std::string(sep == ';' ? "columns are separated by ';'" : "columns are separated by tabs") +
           kSeparatorAdvice;
}

/// Splits a buffer into physical lines. A line ends at "\n", "\r\n" or a lone "\r"; the
/// terminator is not part of the line. Numbers lines from 1.
class LineReader {
public:
    LineReader(const char* begin, const char* end) : p_(begin), end_(end) {}

    bool next(string_view& text) {
        if (p_ == end_) return false;
        ++line_;
        if (nl_ == nullptr || nl_ < p_) find_newline();
        const char* start = p_;
        const char* cr = static_cast<const char*>(
            std::memchr(start, '\r', static_cast<std::size_t>(nl_ - start)));
        if (cr != nullptr && cr + 1 != nl_) {  // lone '\r' (old Mac line end)
            text = string_view(start, static_cast<std::size_t>(cr - start));
            p_ = cr + 1;
        } else {  // "\n", "\r\n", or the last line (maybe ending in a lone '\r')
            const char* text_end = cr != nullptr ? cr : nl_;
            text = string_view(start, static_cast<std::size_t>(text_end - start));
            p_ = nl_ == end_ ? end_ : nl_ + 1;
        }
        return true;
    }

    int line() const { return line_; }
    /// Start of the next line (one past the terminator of the line last returned).
    const char* position() const { return p_; }

private:
    /// Caches the next '\n' at or after p_ (end_ if none), so that files with lone '\r'
    /// line ends are not rescanned for every line.
    void find_newline() {
        const void* hit = std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_));
        nl_ = hit != nullptr ? static_cast<const char*>(hit) : end_;
    }

    const char* p_;
    const char* end_;
    const char* nl_ = nullptr;  // next '\n' at or after p_, or end_; nullptr before the first search
    int line_ = 0;
};

/// The 1-based line holding the byte at `target`.
int line_of_byte(const char* begin, const char* end, const char* target) {
    LineReader lines(begin, end);
    string_view text;
    while (lines.next(text))
        if (target < lines.position()) return lines.line();
    return lines.line();
}

/// A control character that never appears in a text CSV file.
bool is_binary_byte(unsigned char c) {
    return c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f';
}

bool contains_ci(string_view hay, string_view needle) {
    const auto it = std::search(hay.begin(), hay.end(), needle.begin(), needle.end(), [](char a, char b) {
        return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
    });
    return it != hay.end();
}

enum class NumberStatus { ok, not_a_number, not_finite, out_of_range };

/// Parses a trimmed, non-empty cell as a double. Accepts a leading '+'; everything
/// std::from_chars accepts (general format) otherwise. NaN and infinities, and the
/// Microsoft spellings "1.#INF", "1.#QNAN", "-1.#IND", are reported as not finite.
NumberStatus parse_number(string_view s, double& value) {
    const char* b = s.data();
    const char* e = b + s.size();
    if (e - b > 1 && *b == '+' && b[1] != '+' && b[1] != '-') ++b;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (ptr == e && ec == std::errc::result_out_of_range) {
        // Overflow, or underflow below the smallest subnormal. strtod gives +-HUGE_VAL
        // for the first and 0 (or a subnormal) for the second, which is accepted.
        const std::string copy(s);
        char* stop = nullptr;
        const double w = std::strtod(copy.c_str(), &stop);
        if (stop == copy.c_str() + copy.size() && std::isfinite(w)) {
            value = w;
            return NumberStatus::ok;
        }
        return NumberStatus::out_of_range;
    }
    if (ec != std::errc() || ptr != e) {
        for (const char* special : {"#inf", "#ind", "#qnan", "#snan"})
            if (contains_ci(s, special)) return NumberStatus::not_finite;
        return NumberStatus::not_a_number;
    }
    if (!std::isfinite(v)) return NumberStatus::not_finite;
    value = v;
    return NumberStatus::ok;
}

}  // namespace

namespace {

// Where the text starts (after a UTF-8 byte-order mark); refuses UTF-16 and binary content.
const char* text_start(const std::string& fname, const std::string& data) {
    const char* begin = data.data();
    const char* const end = begin + data.size();
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(data[i]); };
    if (data.size() >= 2 && ((byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF)))
        throw InputError(fname, 1, "",
                         "file is not text (binary data at line 1): it looks UTF-16 encoded — save it as "
                         "UTF-8 or ASCII");
    if (data.size() >= 3 && byte(0) == 0xEF && byte(1) == 0xBB && byte(2) == 0xBF) begin += 3;
    for (const char* p = begin; p != end; ++p) {
        if (is_binary_byte(static_cast<unsigned char>(*p))) {
            const int line = line_of_byte(begin, end, p);
            throw InputError(fname, line, "", "file is not text (binary data at line " + std::to_string(line) + ")");
        }
    }
    return begin;
}

// The first line that is neither blank nor a '#' comment: the header row.
string_view header_row(LineReader& lines, const std::string& fname) {
    string_view text;
    bool saw_comment = false;
    while (lines.next(text)) {
        const string_view t = trim(text);
        if (t.empty()) continue;
        if (t.front() == '#') {
            saw_comment = true;
            continue;
        }
        return t;
    }
    // Line 1, as for an empty experiment file: an editor opens the file there.
    if (saw_comment) throw InputError(fname, 1, "", "no header row: the file holds only comments and blank lines");
    throw InputError(fname, 1, "", "file is empty (expected a header row of column names, then one row per sample)");
}

// A data cell's number, or the error naming its line and column.
double cell_value(string_view cell, const std::string& fname, int line, const std::string& column) {
    double value = 0.0;
    switch (parse_number(cell, value)) {
        case NumberStatus::ok:
            return value;
        case NumberStatus::not_finite:
            throw InputError(fname, line, "column " + column, "value is not finite (" + shown(cell) + ")");
        case NumberStatus::out_of_range:
            throw InputError(fname, line, "column " + column, "'" + shown(cell) + "' is out of the range of a double");
        case NumberStatus::not_a_number:
            break;
    }
    if (cell.find('\t') != string_view::npos) throw InputError(fname, line, "", separator_error_text('\t'));
    std::string what = "'" + shown(cell) + "' is not a number";
    if (cell == column)
        what += " (a repeated header row?)";
    else if (cell.find(' ') != string_view::npos)
        what += " (columns must be separated by ',')";
    throw InputError(fname, line, "column " + column, what);
}

}  // namespace

CsvTable CsvTable::read(const std::filesystem::path& file) {
    const std::string fname = file.string();
    const std::string data = read_input_file(file, "data file", kMaxRecordingBytes);

    const char* begin = text_start(fname, data);
    const char* const end = data.data() + data.size();

    CsvTable table;
    table.file_ = file;
    table.content_sha256_ = sha256_of_text(data);

    // Header.
    LineReader lines(begin, end);
    string_view text;
    const string_view header = header_row(lines, fname);
    const int header_line = lines.line();
    table.header_line_ = header_line;

    if (header.find(',') == string_view::npos) {
        const auto semicolons = std::count(header.begin(), header.end(), ';');
        const auto tabs = std::count(header.begin(), header.end(), '\t');
        if (semicolons > 0 || tabs > 0)
            throw InputError(fname, header_line, "", separator_error_text(semicolons >= tabs ? ';' : '\t'));
    }

    for (std::size_t start = 0, index = 1;; ++index) {
        const std::size_t comma = header.find(',', start);
        const string_view raw = trim(header.substr(start, comma == string_view::npos ? string_view::npos : comma - start));
        const string_view name = unquote(raw);
        const std::string position = "column " + std::to_string(index);
        if (name.empty()) throw InputError(fname, header_line, "", position + ": empty column name");
        if (name.size() == raw.size() && (raw.front() == '"' || raw.back() == '"'))
            throw InputError(fname, header_line, "",
                             position + ": unbalanced double quote in column name " + shown(raw));
        // A hash map: a header of 200 000 names is checked in linear time.
        const auto [dup, added] = table.column_index_.emplace(std::string(name), table.names_.size());
        if (!added)
            throw InputError(fname, header_line, "",
                             "column " + std::string(name) + " appears twice (columns " + std::to_string(dup->second + 1) +
                                 " and " + std::to_string(index) + ")");
        table.names_.emplace_back(name);
        if (comma == string_view::npos) break;
        start = comma + 1;
    }

    const std::size_t ncols = table.names_.size();
    {
        double ignored = 0.0;
        const bool all_numbers = std::all_of(table.names_.begin(), table.names_.end(), [&](const std::string& n) {
            return parse_number(n, ignored) == NumberStatus::ok;
        });
        if (all_numbers)
            throw InputError(fname, header_line, "",
                             "no header row: the first row holds numbers (" + shown(header) +
                                 "), but it must name the columns, e.g. time,speed");
    }

    // Data rows.
    const auto newline_count = static_cast<std::size_t>(std::count(begin, end, '\n'));
    table.columns_.assign(ncols, std::vector<double>());
    for (auto& col : table.columns_) col.reserve(newline_count + 1);
    table.row_lines_.reserve(newline_count + 1);

    while (lines.next(text)) {
        const string_view t = trim(text);
        if (t.empty() || t.front() == '#') continue;
        const int line = lines.line();

        if (t.find(';') != string_view::npos) throw InputError(fname, line, "", separator_error_text(';'));
        const auto ncells = static_cast<std::size_t>(std::count(t.begin(), t.end(), ',')) + 1;
        if (ncells < ncols)
            throw InputError(fname, line, "column " + table.names_[ncells],
                             "short row: " + plural(ncells, "value") + ", header has " +
                                 plural(ncols, "column"));
        if (ncells > ncols)
            throw InputError(fname, line, "",
                             "long row: " + plural(ncells, "value") + ", header has " + plural(ncols, "column"));

        std::size_t start = 0;
        for (std::size_t c = 0; c < ncols; ++c) {
            const std::size_t comma = t.find(',', start);
            const string_view cell =
                unquote(trim(t.substr(start, comma == string_view::npos ? string_view::npos : comma - start)));
            start = comma + 1;
            if (cell.empty()) throw InputError(fname, line, "column " + table.names_[c], "empty cell");
            table.columns_[c].push_back(cell_value(cell, fname, line, table.names_[c]));
        }
        table.row_lines_.push_back(line);
    }

    table.rows_ = table.row_lines_.size();
    if (table.rows_ == 0) throw InputError(fname, header_line, "", "no data rows after the header");
    return table;
}

CsvTable CsvTable::from_columns(std::filesystem::path file, std::vector<std::string> names,
                                std::vector<std::vector<double>> columns) {
    CsvTable table;
    table.file_ = std::move(file);
    table.rows_ = columns.empty() ? 0 : columns.front().size();
    for (std::size_t k = 0; k < names.size(); ++k) table.column_index_[names[k]] = k;
    table.names_ = std::move(names);
    table.columns_ = std::move(columns);
    return table;
}

bool CsvTable::has_column(const std::string& name) const { return column_index_.count(name) > 0; }

const std::vector<double>& CsvTable::column(const std::string& name) const {
    const auto it = column_index_.find(name);
    if (it == column_index_.end()) {
        std::string known;
        for (std::size_t i = 0; i < names_.size() && i < 20; ++i) known += (i ? ", " : "") + names_[i];
        if (names_.size() > 20) known += ", ...";
        throw std::out_of_range(file_.string() + ": no column '" + name + "' (columns: " + known + ")");
    }
    return columns_[it->second];
}

void CsvTable::require_strictly_increasing(const std::string& name) const {
    const std::vector<double>& v = column(name);
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (v[i] > v[i - 1]) continue;
        throw InputError(file_.string(), line_of_row(i), "column " + name,
                         "values must be strictly increasing: " + format_double(v[i]) + " after " +
                             format_double(v[i - 1]) + (v[i] == v[i - 1] ? " (repeated)" : " (decreasing)"));
    }
}

}  // namespace tvid
