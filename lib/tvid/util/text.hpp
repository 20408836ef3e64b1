#pragma once
// Small text helpers for messages: word lists and numbers as a user typed them.

#include <string>
#include <vector>

namespace tvid {

/// "a, b, c"
std::string join_words(const std::vector<std::string>& words);

/// A number in the shortest form that reads back to 10 significant digits (%.10g).
std::string number_text(double value);

}  // namespace tvid
