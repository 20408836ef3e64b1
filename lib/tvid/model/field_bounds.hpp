#pragma once
// The values a field can take, where an element kind checks a rule between its fields
// (limits that hold zero, stage angles in order, an efficiency of at most 1): a constant's
// own value, a parameter's bounds. An element is checked when it is read (its constants)
// and again once the parameters are read (experiment/parameter_reader.cpp). A rule on one
// field, like a sign, holds for every value of a parameter's bounds (an efficiency's max at
// most 1, a lower limit's max at most 0); an order between two fields is refused when no
// values of their bounds keep it (overlapping boxes of a Coulomb and a breakaway torque are
// a search, bounds that put the second stage before the first are a mistake).

#include <initializer_list>
#include <string>

#include "tvid/model/field.hpp"

namespace tvid {

class FieldBounds {
public:
    virtual ~FieldBounds() = default;
    /// Whether f's values are known here: a constant always, a parameter once its bounds are read.
    virtual bool known(const Field& f) const = 0;
    /// The smallest and the largest value f can take (a constant's own value).
    virtual double lowest(const Field& f) const = 0;
    virtual double highest(const Field& f) const = 0;
    /// f as a message gives it: "0.6", or "L (bounds [0.1, 2])".
    virtual std::string text(const Field& f) const = 0;
    /// Reports a broken rule: at the element's `key` when `involved` are constants, else at
    /// the bounds of the first parameter among them.
    [[noreturn]] virtual void fail(const char* key, std::initializer_list<Field> involved,
                                   const std::string& problem) const = 0;
};

}  // namespace tvid
