#pragma once
// JSON files tvid reads (parameter files, references, fit reports, batch records): read
// through read_input_file (a regular file, at most kMaxJsonBytes), nested at most
// kMaxJsonDepth deep (a deeper file would only exhaust the stack of whatever walks it), and
// without a key twice in one object (JSON leaves duplicates undefined; the last value
// silently winning would hide a mistake in a reference). Each refusal is one InputError
// naming the file and the line.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/io/input_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

inline constexpr int kMaxJsonDepth = 64;

/// The 1-based line of byte `offset` of `text`.
inline int line_at_byte(const std::string& text, std::size_t offset) {
    offset = std::min(offset, text.size());
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

/// The one-line refusal of a number too large for a double: "ref.json:3: cost: '1e400' is
/// too large for a number (at most about 1.8e308)", the line that of the number's first
/// appearance in the text, the key that of the value being read.
[[noreturn]] inline void throw_number_out_of_range(const std::string& text, const std::string& name,
                                                   const std::string& what, const std::string& key) {
    // nlohmann's message: "[json.exception.out_of_range.406] number overflow parsing '1e400'"
    const auto open = what.find('\''), close = what.rfind('\'');
    const std::string number = open != std::string::npos && close > open ? what.substr(open + 1, close - open - 1) : "";
    int line = 0;
    if (!number.empty())
        for (std::size_t at = text.find(number); at != std::string::npos; at = text.find(number, at + 1)) {
            const auto part_of_number = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+'; };
            if ((at > 0 && part_of_number(text[at - 1])) ||
                (at + number.size() < text.size() && part_of_number(text[at + number.size()])))
                continue;
            line = line_at_byte(text, at);
            break;
        }
    throw InputError(name, line, key,
                     number.empty() ? std::string("a number is too large (at most about 1.8e308)")
                                    : "'" + number + "' is too large for a number (at most about 1.8e308)");
}

/// Parses `text` (the content of `name`) as Json (nlohmann::json or nlohmann::ordered_json).
template <class Json = nlohmann::json>
Json parse_json_text(const std::string& text, const std::string& name) {
    std::vector<std::set<std::string>> keys;  // the keys seen in each open object, innermost last
    std::string problem;
    std::string last_key;  // the key whose value is being read (for a number out of range)
    auto check = [&](int depth, typename Json::parse_event_t event, Json& parsed) {
        using E = typename Json::parse_event_t;
        // `depth` is that of the enclosing value: the new object or array is at depth + 1.
        if ((event == E::object_start || event == E::array_start) && depth + 1 > kMaxJsonDepth) {
            problem = "nested more than " + std::to_string(kMaxJsonDepth) + " levels deep";
            throw std::length_error(problem);
        }
        if (event == E::key) last_key = parsed.template get<std::string>();
        if (event == E::object_start) keys.emplace_back();
        if (event == E::object_end && !keys.empty()) keys.pop_back();
        if (event == E::key && !keys.empty() && !keys.back().insert(parsed.template get<std::string>()).second) {
            problem = "the key \"" + parsed.template get<std::string>() + "\" appears twice in one object";
            throw std::invalid_argument(problem);
        }
        return true;
    };
    try {
        return Json::parse(text, check);
    } catch (const typename Json::parse_error& e) {
        throw InputError(name, line_at_byte(text, e.byte > 0 ? e.byte - 1 : 0), "",
                         std::string("not valid JSON: ") + e.what());
    } catch (const typename Json::out_of_range& e) {
        // A number beyond a double (1e400): nlohmann names the number, not where it is.
        throw_number_out_of_range(text, name, e.what(), last_key);
    } catch (const typename Json::exception& e) {
        throw InputError(name, 0, "", std::string("not valid JSON: ") + e.what());
    } catch (const std::logic_error&) {
        // Thrown by the check above, at the offending value: no position is known, so the
        // line is left out rather than guessed.
        throw InputError(name, 0, "", problem);
    }
}

/// Reads and parses the JSON file `file`; `what` names it in messages ("reference file").
template <class Json = nlohmann::json>
Json read_json_file(const std::filesystem::path& file, const std::string& what) {
    return parse_json_text<Json>(read_input_file(file, what, kMaxJsonBytes), file.string());
}

}  // namespace tvid
