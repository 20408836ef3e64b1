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

/// A fraction in whole percent ("38 %", "4 %").
std::string whole_percent(double fraction);

/// A fraction as a person reads a percentage: whole percent from 10 % up ("38 %"), two
/// significant digits below ("4.2 %", "0.13 %"), so that a small share never reads "0 %".
std::string readable_percent(double fraction);

/// Levenshtein distance (insertions, deletions, substitutions): how near a typo is, for
/// "did you mean" on a misspelt key or command.
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace tvid
