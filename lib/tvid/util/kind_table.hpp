#pragma once
// What every table of kinds (integration methods, initial-state kinds) asks of its rows: one
// row per enumerator, in the enumerators' order (so a kind's row is rows[kind]), checked at
// compile time; and a row found by its name. A row has `kind` (its enumerator) and `name`. An
// enumeration that needs only its names is a table of EnumName rows.

#include <array>
#include <cstddef>
#include <string_view>

namespace tvid {

/// Row i's kind is enumerator i, and there are `count` enumerators.
template <class Row, std::size_t N>
consteval bool rows_in_enumerator_order(const std::array<Row, N>& rows, std::size_t count) {
    for (std::size_t i = 0; i < N; ++i)
        if (static_cast<std::size_t>(rows[i].kind) != i) return false;
    return N == count;
}

/// The row named `name`, or nullptr.
template <class Row, std::size_t N>
constexpr const Row* find_row_named(const std::array<Row, N>& rows, std::string_view name) {
    for (const Row& row : rows)
        if (name == row.name) return &row;
    return nullptr;
}

/// An enumerator and its name, for an enumeration named by a table (rows in enumerator order).
template <class Enum>
struct EnumName {
    Enum kind;
    const char* name;
};

/// The name of `value` in rows checked by rows_in_enumerator_order.
template <class Enum, std::size_t N>
constexpr const char* name_in(const std::array<EnumName<Enum>, N>& rows, Enum value) {
    const auto i = static_cast<std::size_t>(value);
    return i < N ? rows[i].name : "?";
}

}  // namespace tvid
