#pragma once
// The text of a JSON document as tvid writes it (report files, standard output). Strings
// that are not valid UTF-8 (a path or a name with a Latin-1 byte) are written with U+FFFD
// in place of each bad byte: the report is written, never lost to an encoding error
// after the work is done.

#include <nlohmann/json.hpp>
#include <string>

namespace tvid {

inline std::string json_text(const nlohmann::json& j, int indent = 2) {
    return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace tvid
