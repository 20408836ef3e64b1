#pragma once
// Small text helpers for messages: word lists and numbers as a user typed them.

#include <cstddef>
#include <string>
#include <vector>

namespace tvid {

/// "a, b, c"
std::string join_words(const std::vector<std::string>& words);

/// A number in the shortest form that reads back to 10 significant digits (%.10g).
std::string number_text(double value);

/// Levenshtein distance (insertions, deletions, substitutions): how near a typo is, for
/// "did you mean" on a misspelt key or command.
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace tvid
