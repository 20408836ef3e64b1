// Unit tests for tvid::CsvTable::read and its helpers.

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "tvid/io/csv_table.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

namespace fs = std::filesystem;
using tvid::CsvTable;
using tvid::InputError;
using Catch::Matchers::Contains;

namespace {

/// A fresh, uniquely named directory under the system temp directory, removed at the end.
class TempDir {
public:
    TempDir() {
        static std::atomic<unsigned> counter{0};
        std::random_device rd;
        const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
        for (int attempt = 0;; ++attempt) {
            const std::string leaf = "tvid_csv_test_" + std::to_string(stamp) + "_" + std::to_string(rd()) + "_" +
                                     std::to_string(counter++);
            path_ = fs::temp_directory_path() / leaf;
            if (fs::create_directory(path_)) break;
            if (attempt > 100) throw std::runtime_error("cannot create a temporary directory");
        }
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const fs::path& path() const { return path_; }

    /// Writes `content` byte for byte to a file in this directory.
    fs::path write(const std::string& name, const std::string& content) const {
        const fs::path file = path_ / name;
        std::ofstream out(file, std::ios::binary);
        out.write(content.data(), static_cast<std::streamsize>(content.size()));
        out.close();
        REQUIRE(out.good());
        return file;
    }

private:
    fs::path path_;
};

/// Reads `content` as a CSV file and returns the InputError it must raise.
InputError error_for(const std::string& content) {
    TempDir dir;
    const fs::path file = dir.write("data.csv", content);
    try {
        CsvTable::read(file);
    } catch (const InputError& e) {
        CHECK(e.file() == file.string());
        return e;
    }
    FAIL("expected an InputError for:\n" << content);
    throw std::logic_error("unreachable");
}

CsvTable table_for(const TempDir& dir, const std::string& content) {
    return CsvTable::read(dir.write("data.csv", content));
}

const std::string kSeparatorAdvice =
    "tvid reads comma-separated files (',' between columns, '.' as decimal point)";

}  // namespace

// --------------------------------------------------------------------------------------
// Happy path

TEST_CASE("CsvTable reads names, values and line numbers", "[csv]") {
    TempDir dir;
    const fs::path file = dir.write("plain.csv",
                                    "time,speed,torque\n"
                                    "0,1.5,-2\n"
                                    "0.001,2.25e3,3E-2\n"
                                    "0.002,-0.5,7\n");
    const CsvTable t = CsvTable::read(file);

    CHECK(t.file() == file);
    REQUIRE(t.column_names() == std::vector<std::string>{"time", "speed", "torque"});
    REQUIRE(t.rows() == 3);
    CHECK(t.header_line() == 1);
    CHECK(t.line_of_row(0) == 2);
    CHECK(t.line_of_row(1) == 3);
    CHECK(t.line_of_row(2) == 4);
    CHECK_THROWS_AS(t.line_of_row(3), std::out_of_range);

    CHECK(t.column("time") == std::vector<double>{0.0, 0.001, 0.002});
    CHECK(t.column("speed") == std::vector<double>{1.5, 2250.0, -0.5});
    CHECK(t.column("torque") == std::vector<double>{-2.0, 0.03, 7.0});

    CHECK(t.has_column("speed"));
    CHECK_FALSE(t.has_column("Speed"));
    CHECK_FALSE(t.has_column(""));
    CHECK_THROWS_AS(t.column("rpm"), std::out_of_range);
    CHECK_THROWS_AS(t.column(""), std::out_of_range);
}

TEST_CASE("CsvTable skips comments and blank lines everywhere and keeps physical line numbers", "[csv]") {
    TempDir dir;
    const CsvTable t = table_for(dir,
                                 "# recorded 2024-01-01\n"     // 1
                                 "\n"                          // 2
                                 "   # indented comment\n"     // 3
                                 "t, x\n"                      // 4 header
                                 "# between header and data\n" // 5
                                 "1, 10\n"                     // 6
                                 "   \t \n"                    // 7 blank (whitespace only)
                                 "\t# tab-indented comment\n"  // 8
                                 "2, 20\n"                     // 9
                                 "\n"                          // 10
                                 "3,30\n"                      // 11
                                 "# trailing comment\n"        // 12
                                 "\n");                        // 13
    REQUIRE(t.column_names() == std::vector<std::string>{"t", "x"});
    CHECK(t.header_line() == 4);
    REQUIRE(t.rows() == 3);
    CHECK(t.line_of_row(0) == 6);
    CHECK(t.line_of_row(1) == 9);
    CHECK(t.line_of_row(2) == 11);
    CHECK(t.column("t") == std::vector<double>{1, 2, 3});
    CHECK(t.column("x") == std::vector<double>{10, 20, 30});
}

TEST_CASE("CsvTable accepts a UTF-8 byte-order mark", "[csv]") {
    TempDir dir;
    SECTION("BOM before the header") {
        const CsvTable t = table_for(dir, "\xEF\xBB\xBFtime,y\n0,1\n");
        REQUIRE(t.column_names() == std::vector<std::string>{"time", "y"});
        CHECK(t.header_line() == 1);
        CHECK(t.line_of_row(0) == 2);
        CHECK(t.column("time") == std::vector<double>{0.0});
    }
    SECTION("BOM before a comment") {
        const CsvTable t = table_for(dir, "\xEF\xBB\xBF# comment\ntime,y\n0,1\n");
        REQUIRE(t.column_names() == std::vector<std::string>{"time", "y"});
        CHECK(t.header_line() == 2);
        CHECK(t.line_of_row(0) == 3);
    }
}

TEST_CASE("CsvTable accepts CRLF, lone CR and a missing final newline", "[csv]") {
    TempDir dir;
    SECTION("CRLF") {
        const CsvTable t = table_for(dir, "# c\r\na,b\r\n\r\n1,2\r\n3,4\r\n");
        REQUIRE(t.column_names() == std::vector<std::string>{"a", "b"});
        CHECK(t.header_line() == 2);
        REQUIRE(t.rows() == 2);
        CHECK(t.line_of_row(0) == 4);
        CHECK(t.line_of_row(1) == 5);
        CHECK(t.column("b") == std::vector<double>{2, 4});
    }
    SECTION("old Mac CR line ends") {
        const CsvTable t = table_for(dir, "a,b\r1,2\r\r3,4\r");
        REQUIRE(t.rows() == 2);
        CHECK(t.line_of_row(0) == 2);
        CHECK(t.line_of_row(1) == 4);
        CHECK(t.column("a") == std::vector<double>{1, 3});
    }
    SECTION("no newline after the last row") {
        const CsvTable t = table_for(dir, "a,b\n1,2\n3,4");
        REQUIRE(t.rows() == 2);
        CHECK(t.column("b") == std::vector<double>{2, 4});
        CHECK(t.line_of_row(1) == 3);
    }
}

TEST_CASE("CsvTable trims names and cells and removes double quotes", "[csv]") {
    TempDir dir;
    const CsvTable t = table_for(dir,
                                 "  \"time\" ,\" engine speed \",\tTds\t\n"
                                 " 1 , \"2.5\" ,\t3\t\n");
    REQUIRE(t.column_names() == std::vector<std::string>{"time", "engine speed", "Tds"});
    CHECK(t.column("time") == std::vector<double>{1});
    CHECK(t.column("engine speed") == std::vector<double>{2.5});
    CHECK(t.column("Tds") == std::vector<double>{3});
}

TEST_CASE("CsvTable number syntax", "[csv]") {
    TempDir dir;
    const CsvTable t = table_for(dir,
                                 "v\n"
                                 "+1.5\n"
                                 "-0.25\n"
                                 ".5\n"
                                 "2.\n"
                                 "1e3\n"
                                 "+2.5E-3\n"
                                 "-7\n"
                                 "0.1\n"
                                 "1e-400\n");  // underflows to zero: accepted
    const auto& v = t.column("v");
    REQUIRE(v.size() == 9);
    CHECK(v[0] == 1.5);
    CHECK(v[1] == -0.25);
    CHECK(v[2] == 0.5);
    CHECK(v[3] == 2.0);
    CHECK(v[4] == 1000.0);
    CHECK(v[5] == 0.0025);
    CHECK(v[6] == -7.0);
    CHECK(v[7] == 0.1);  // exact decimal-to-double conversion
    CHECK(v[8] == 0.0);
}

TEST_CASE("CsvTable single column and repeated reads", "[csv]") {
    TempDir dir;
    const fs::path file = dir.write("one.csv", "only\n42\n");
    const CsvTable a = CsvTable::read(file);
    const CsvTable b = CsvTable::read(file);
    CHECK(a.column_names() == std::vector<std::string>{"only"});
    CHECK(a.column("only") == std::vector<double>{42});
    CHECK(b.column("only") == a.column("only"));
}

TEST_CASE("CsvTable reads a large file exactly", "[csv][large]") {
    constexpr std::size_t kRows = 13000;
    constexpr std::size_t kCols = 17;
    std::string content = "# generated\n";
    for (std::size_t c = 0; c < kCols; ++c) content += (c ? "," : "") + ("ch" + std::to_string(c));
    content += "\r\n";
    for (std::size_t r = 0; r < kRows; ++r) {
        for (std::size_t c = 0; c < kCols; ++c) {
            char buf[64];
            const double value = static_cast<double>(r) * 0.001 + static_cast<double>(c) * 1e-7 - 3.0;
            std::snprintf(buf, sizeof buf, "%s%.17g", c ? ", " : "", value);
            content += buf;
        }
        content += "\r\n";
    }
    TempDir dir;
    const CsvTable t = table_for(dir, content);
    REQUIRE(t.rows() == kRows);
    REQUIRE(t.column_names().size() == kCols);
    CHECK(t.column_names().back() == "ch16");
    CHECK(t.header_line() == 2);
    CHECK(t.line_of_row(kRows - 1) == static_cast<int>(kRows) + 2);
    for (std::size_t c = 0; c < kCols; ++c) {
        const auto& col = t.column("ch" + std::to_string(c));
        REQUIRE(col.size() == kRows);
        for (std::size_t r = 0; r < kRows; r += 997)
            CHECK(col[r] == static_cast<double>(r) * 0.001 + static_cast<double>(c) * 1e-7 - 3.0);
        CHECK(col.back() == static_cast<double>(kRows - 1) * 0.001 + static_cast<double>(c) * 1e-7 - 3.0);
    }
    CHECK_NOTHROW(t.require_strictly_increasing("ch0"));
}

// --------------------------------------------------------------------------------------
// File-level errors

TEST_CASE("CsvTable reports a missing or unreadable file", "[csv][error]") {
    TempDir dir;
    SECTION("missing file") {
        const fs::path file = dir.path() / "does_not_exist.csv";
        try {
            CsvTable::read(file);
            FAIL("no exception");
        } catch (const InputError& e) {
            CHECK(e.file() == file.string());
            CHECK(e.line() == 0);
            CHECK(e.key().empty());
            CHECK(e.problem() == "no such data file");
            CHECK(std::string(e.what()) == file.string() + ": " + e.problem());
        }
    }
    SECTION("directory") {
        try {
            CsvTable::read(dir.path());
            FAIL("no exception");
        } catch (const InputError& e) {
            CHECK(e.line() == 0);
            CHECK(e.key().empty());
            CHECK(e.problem() == "the data file is a directory, not a file");
        }
    }
}

TEST_CASE("CsvTable rejects an empty file or one without a header", "[csv][error]") {
    SECTION("zero bytes") {
        const InputError e = error_for("");
        CHECK(e.line() == 1);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("file is empty"));
    }
    SECTION("only a BOM") {
        CHECK_THAT(error_for("\xEF\xBB\xBF").problem(), Contains("file is empty"));
    }
    SECTION("only blank lines") {
        CHECK_THAT(error_for("\n  \n\t\r\n").problem(), Contains("file is empty"));
    }
    SECTION("only comments") {
        const InputError e = error_for("# a\n\n  # b\n");
        CHECK(e.line() == 1);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("no header row"));
    }
    SECTION("first row holds numbers") {
        const InputError e = error_for("# c\n0,1.5,2\n1,2,3\n");
        CHECK(e.line() == 2);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("no header row"));
    }
}

TEST_CASE("CsvTable rejects binary content", "[csv][error]") {
    SECTION("NUL byte on line 3") {
        const InputError e = error_for(std::string("t,x\n1,2\n3,\0\n", 12));
        CHECK(e.line() == 3);
        CHECK(e.key().empty());
        CHECK(e.problem() == "file is not text (binary data at line 3)");
    }
    SECTION("control byte after CRLF lines and a BOM") {
        const InputError e = error_for("\xEF\xBB\xBFt,x\r\n1,2\r\n\r\n4,\x01\r\n");
        CHECK(e.line() == 4);
        CHECK(e.problem() == "file is not text (binary data at line 4)");
    }
    SECTION("zip archive (e.g. an .xlsx)") {
        const InputError e = error_for(std::string("PK\x03\x04\x14\x00\x06\x00", 8));
        CHECK(e.line() == 1);
        CHECK_THAT(e.problem(), Contains("file is not text (binary data at line 1)"));
    }
    SECTION("UTF-16") {
        const InputError e = error_for(std::string("\xFF\xFEt\0,\0x\0\n\0", 10));
        CHECK(e.line() == 1);
        CHECK_THAT(e.problem(), Contains("file is not text"));
        CHECK_THAT(e.problem(), Contains("UTF-16"));
    }
}

// --------------------------------------------------------------------------------------
// Header errors

TEST_CASE("CsvTable rejects empty column names", "[csv][error]") {
    SECTION("middle") {
        const InputError e = error_for("# c\nt,,x\n1,2,3\n");
        CHECK(e.line() == 2);
        CHECK(e.key().empty());
        CHECK(e.problem() == "column 2: empty column name");
    }
    SECTION("trailing comma") {
        const InputError e = error_for("t,x,\n1,2,3\n");
        CHECK(e.line() == 1);
        CHECK(e.problem() == "column 3: empty column name");
    }
    SECTION("blank between commas") {
        CHECK(error_for(" , t\n1,2\n").problem() == "column 1: empty column name");
    }
    SECTION("empty quotes") {
        CHECK(error_for("t,\"  \"\n1,2\n").problem() == "column 2: empty column name");
    }
    SECTION("unbalanced quote") {
        const InputError e = error_for("t,\"x\n1,2\n");
        CHECK(e.line() == 1);
        CHECK_THAT(e.problem(), Contains("column 2") && Contains("quote"));
    }
}

TEST_CASE("CsvTable rejects duplicate column names", "[csv][error]") {
    SECTION("plain") {
        const InputError e = error_for("\nt,x,t\n1,2,3\n");
        CHECK(e.line() == 2);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("column t appears twice"));
    }
    SECTION("after trimming and unquoting") {
        const InputError e = error_for("speed, \"speed\" \n1,2\n");
        CHECK(e.line() == 1);
        CHECK_THAT(e.problem(), Contains("column speed appears twice"));
    }
}

TEST_CASE("CsvTable rejects semicolon and tab separated files", "[csv][error]") {
    SECTION("semicolon header") {
        const InputError e = error_for("# export\ntime;speed\n0,5;1,2\n");
        CHECK(e.line() == 2);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("columns are separated by ';'"));
        CHECK_THAT(e.problem(), Contains(kSeparatorAdvice));
    }
    SECTION("tab header") {
        const InputError e = error_for("time\tspeed\n0.5\t1.2\n");
        CHECK(e.line() == 1);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("columns are separated by tab"));
        CHECK_THAT(e.problem(), Contains(kSeparatorAdvice));
        CHECK_THAT(e.problem(), !Contains("';'"));
    }
    SECTION("semicolon in a data row of a comma file") {
        const InputError e = error_for("time,speed\n0,1\n1;2\n");
        CHECK(e.line() == 3);
        CHECK(e.key().empty());
        CHECK_THAT(e.problem(), Contains("columns are separated by ';'"));
        CHECK_THAT(e.problem(), Contains(kSeparatorAdvice));
    }
    SECTION("tab in a data row of a one-column file") {
        const InputError e = error_for("time\n0\n1\t2\n");
        CHECK(e.line() == 3);
        CHECK_THAT(e.problem(), Contains("columns are separated by tab"));
    }
    SECTION("a trailing tab on a one-column header is only whitespace") {
        TempDir dir;
        const CsvTable t = table_for(dir, "time\t\n1\n");
        CHECK(t.column_names() == std::vector<std::string>{"time"});
    }
}

// --------------------------------------------------------------------------------------
// Data row errors

TEST_CASE("CsvTable rejects short and long rows", "[csv][error]") {
    SECTION("short row names the first missing column") {
        const InputError e = error_for("t,x,y\n1,2,3\n\n4,5\n");
        CHECK(e.line() == 4);
        CHECK(e.key() == "column y");
        CHECK(e.problem() == "short row: 2 values, header has 3 columns");
    }
    SECTION("one value") {
        const InputError e = error_for("t,x,y\n1\n");
        CHECK(e.line() == 2);
        CHECK(e.key() == "column x");
        CHECK(e.problem() == "short row: 1 value, header has 3 columns");
    }
    SECTION("long row") {
        const InputError e = error_for("t,x\r\n1,2\r\n3,4,5,6\r\n");
        CHECK(e.line() == 3);
        CHECK(e.key().empty());
        CHECK(e.problem() == "long row: 4 values, header has 2 columns");
    }
    SECTION("trailing comma makes a long row") {
        const InputError e = error_for("t\n1,\n");
        CHECK(e.line() == 2);
        CHECK(e.problem() == "long row: 2 values, header has 1 column");
    }
}

TEST_CASE("CsvTable rejects empty cells", "[csv][error]") {
    SECTION("empty") {
        const InputError e = error_for("t,x,y\n1,,3\n");
        CHECK(e.line() == 2);
        CHECK(e.key() == "column x");
        CHECK(e.problem() == "empty cell");
        CHECK(std::string(e.what()) == e.file() + ":2: column x: empty cell");
    }
    SECTION("whitespace only, last column") {
        const InputError e = error_for("t,x,y\n1,2,3\n# c\n1,2,  \t\n");
        CHECK(e.line() == 4);
        CHECK(e.key() == "column y");
        CHECK(e.problem() == "empty cell");
    }
    SECTION("empty quotes") {
        const InputError e = error_for("t,x\n\"\",2\n");
        CHECK(e.key() == "column t");
        CHECK(e.problem() == "empty cell");
    }
}

TEST_CASE("CsvTable rejects non-numeric cells", "[csv][error]") {
    struct Case {
        std::string cell;
        std::string shown;
    };
    const std::vector<Case> cases = {
        {"abc", "abc"},     {"1.2.3", "1.2.3"}, {"0x10", "0x10"}, {"1e", "1e"},     {"+-1", "+-1"},
        {"--1", "--1"},     {"++1", "++1"},     {"+", "+"},       {"-", "-"},       {".", "."},
        {"12rpm", "12rpm"}, {"#N/A", "#N/A"},   {"\"3", "\"3"},   {"e5", "e5"},
    };
    for (const auto& c : cases) {
        DYNAMIC_SECTION("cell " << c.cell) {
            const InputError e = error_for("t,speed\n0,1\n\n1," + c.cell + "\n");
            CHECK(e.line() == 4);
            CHECK(e.key() == "column speed");
            CHECK(e.problem() == "'" + c.shown + "' is not a number");
        }
    }
    SECTION("space separated values get a hint") {
        const InputError e = error_for("t x\n0 1\n");
        CHECK(e.line() == 2);
        CHECK(e.key() == "column t x");
        CHECK_THAT(e.problem(), Contains("'0 1' is not a number") && Contains("separated by ','"));
    }
    SECTION("a repeated header row gets a hint") {
        const InputError e = error_for("t,x\n0,1\nt,x\n");
        CHECK(e.line() == 3);
        CHECK(e.key() == "column t");
        CHECK_THAT(e.problem(), Contains("'t' is not a number") && Contains("header"));
    }
    SECTION("a very long cell is shortened in the message") {
        const std::string junk(500, 'z');
        const InputError e = error_for("t\n" + junk + "\n");
        CHECK(e.key() == "column t");
        CHECK(e.problem().size() < 100);
        CHECK_THAT(e.problem(), Contains("...' is not a number"));
    }
}

TEST_CASE("CsvTable rejects NaN and infinities", "[csv][error]") {
    for (const std::string spelling : {"nan", "NaN", "NAN", "-nan", "nan(0x1)", "inf", "Inf", "-inf", "+inf",
                                       "INF", "Infinity", "-Infinity", "infinity", "1.#INF", "-1.#IND",
                                       "1.#QNAN"}) {
        DYNAMIC_SECTION("value " << spelling) {
            const InputError e = error_for("t,x\n0,1\n# gap\n1, " + spelling + " \n");
            CHECK(e.line() == 4);
            CHECK(e.key() == "column x");
            CHECK(e.problem() == "value is not finite (" + spelling + ")");
        }
    }
    SECTION("overflow") {
        const InputError e = error_for("t\n1e400\n");
        CHECK(e.line() == 2);
        CHECK(e.key() == "column t");
        CHECK_THAT(e.problem(), Contains("1e400") && Contains("range"));
    }
}

TEST_CASE("CsvTable rejects a file without data rows", "[csv][error]") {
    SECTION("header only") {
        const InputError e = error_for("t,x\n");
        CHECK(e.line() == 1);
        CHECK(e.key().empty());
        CHECK(e.problem() == "no data rows after the header");
    }
    SECTION("header followed by comments and blank lines") {
        const InputError e = error_for("\n# c\nt,x\n# nothing\n\n   \n");
        CHECK(e.line() == 3);
        CHECK(e.problem() == "no data rows after the header");
    }
}

// --------------------------------------------------------------------------------------
// require_strictly_increasing

TEST_CASE("CsvTable::require_strictly_increasing", "[csv]") {
    TempDir dir;
    const CsvTable t = table_for(dir,
                                 "time,rep,dec,up\n"  // 1
                                 "0,0.5,1,1\n"        // 2
                                 "# c\n"              // 3
                                 "0.1,0.5,0.5,2\n"    // 4
                                 "\n"                 // 5
                                 "0.2,0.6,0.4,3\n");  // 6
    CHECK_NOTHROW(t.require_strictly_increasing("time"));
    CHECK_NOTHROW(t.require_strictly_increasing("up"));
    CHECK_THROWS_AS(t.require_strictly_increasing("nope"), std::out_of_range);

    try {
        t.require_strictly_increasing("rep");
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(e.file() == t.file().string());
        CHECK(e.line() == 4);
        CHECK(e.key() == "column rep");
        CHECK(e.problem() == "values must be strictly increasing: 0.5 after 0.5 (repeated)");
    }
    try {
        t.require_strictly_increasing("dec");
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(e.line() == 4);
        CHECK(e.key() == "column dec");
        CHECK(e.problem() == "values must be strictly increasing: 0.5 after 1 (decreasing)");
    }

    const CsvTable late = table_for(dir, "t\n1\n2\n\n3\n2.5\n");
    try {
        late.require_strictly_increasing("t");
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(e.line() == 6);
        CHECK(e.key() == "column t");
        CHECK(e.problem() == "values must be strictly increasing: 2.5 after 3 (decreasing)");
    }

    const CsvTable single = table_for(dir, "t\n7\n");
    CHECK_NOTHROW(single.require_strictly_increasing("t"));
}

}  // namespace TVID_UNITY_ID
