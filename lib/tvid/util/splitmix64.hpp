#pragma once
// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed, portable 64-bit stream from any
// state, for draws that must be the same on every machine and thread count (multistart's
// start points, tvid design's parameter draws).

#include <cstdint>

namespace tvid {

inline std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

}  // namespace tvid
