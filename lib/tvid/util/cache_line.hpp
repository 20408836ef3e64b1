#pragma once
// The size of a cache line on the x86-64 machines tvid is built for.

#include <cstddef>

namespace tvid {

/// What a per-thread workspace aligns to (alignas(kCacheLine)): it then starts a line and
/// fills whole lines, so that no other allocation shares a line with it. One thread's
/// writes (its inputs, torques, counters) would otherwise evict the line another thread
/// reads its own model's pointers from at every right-hand side (false sharing).
inline constexpr std::size_t kCacheLine = 64;

}  // namespace tvid
