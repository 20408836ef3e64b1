#pragma once
// JSON files tvid reads (parameter files, references, fit reports, batch records): read
// through read_input_file (a regular file, at most kMaxJsonBytes), nested at most
// kMaxJsonDepth deep (a deeper file would only exhaust the stack of whatever walks it), and
// without a key twice in one object (JSON leaves duplicates undefined; the last value
// silently winning would hide a mistake in a reference). Each refusal is one InputError
// naming the file and the line.

#include <algorithm>
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

/// Parses `text` (the content of `name`) as Json (nlohmann::json or nlohmann::ordered_json).
template <class Json = nlohmann::json>
Json parse_json_text(const std::string& text, const std::string& name) {
    std::vector<std::set<std::string>> keys;  // the keys seen in each open object, innermost last
    std::string problem;
    auto check = [&](int depth, typename Json::parse_event_t event, Json& parsed) {
        using E = typename Json::parse_event_t;
        // `depth` is that of the enclosing value: the new object or array is at depth + 1.
        if ((event == E::object_start || event == E::array_start) && depth + 1 > kMaxJsonDepth) {
            problem = "nested more than " + std::to_string(kMaxJsonDepth) + " levels deep";
            throw std::length_error(problem);
        }
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
