#include "tvid/parallel/string_list.hpp"

#include <stdexcept>

namespace tvid {

std::string encode_string_list(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += std::to_string(s.size()) + ':' + s;
    return out;
}

std::vector<std::string> decode_string_list(const std::string& message) {
    std::vector<std::string> items;
    std::size_t at = 0;
    while (at < message.size()) {
        const std::size_t colon = message.find(':', at);
        if (colon == std::string::npos || colon == at || colon - at > 18 ||
            message.find_first_not_of("0123456789", at) != colon)
            throw std::runtime_error("malformed message between processes");
        const std::size_t length = std::stoull(message.substr(at, colon - at));
        if (length > message.size() - colon - 1) throw std::runtime_error("truncated message between processes");
        items.push_back(message.substr(colon + 1, length));
        at = colon + 1 + length;
    }
    return items;
}

}  // namespace tvid
