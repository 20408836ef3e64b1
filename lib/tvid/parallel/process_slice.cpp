#include "tvid/parallel/process_group.hpp"

namespace tvid {

ProcessSlice process_slice(std::size_t count, int rank, int size) {
    const auto r = static_cast<std::size_t>(rank), n = static_cast<std::size_t>(size);
    return ProcessSlice{count * r / n, count * (r + 1) / n};
}

}  // namespace tvid
