#pragma once
// A text cell of a CSV file tvid writes, per RFC 4180: as it is, or, when it holds a comma,
// a double quote, a CR or an LF, in double quotes with each quote doubled. Every name a
// report writes into a CSV (an output, a parameter, a window, a node, a message) goes
// through here, so that a name such as "w, rad/s" stays one cell.

#include <string>
#include <string_view>

namespace tvid {

inline std::string csv_field(std::string_view text) {
    if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + '"';
}

}  // namespace tvid
