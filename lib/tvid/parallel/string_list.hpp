#pragma once
// A list of strings as one message between processes: each string as its length in
// decimal, a colon and its bytes, so any byte (commas, quotes, line breaks) goes through.

#include <string>
#include <vector>

namespace tvid {

std::string encode_string_list(const std::vector<std::string>& items);

/// Throws std::runtime_error on a message that encode_string_list did not write.
std::vector<std::string> decode_string_list(const std::string& message);

}  // namespace tvid
