#pragma once
// Boost 1.74's uBLAS (the vectors, matrices and LU of odeint's rosenbrock4) under C++20:
// its unbounded_array constructs and destroys elements through std::allocator::construct
// and ::destroy, which C++20 removed (boostorg/ublas#95, fixed upstream by #103 in later
// Boost releases). For the two element types rosenbrock4 stores — double, and std::size_t
// for the LU's permutation — the two members that make those calls are given here in
// explicit specializations that need no construct/destroy: both types are trivial, so
// allocating, copying and freeing is all there is to do. Include this right after the
// uBLAS headers and before any use of rosenbrock4.

#include <algorithm>
#include <boost/numeric/ublas/storage.hpp>
#include <boost/version.hpp>
#include <cstddef>
#include <memory>

#if BOOST_VERSION < 107600 && __cplusplus > 201703L

// The sized constructor and resize of unbounded_array<T> for a trivial T.
#define TVID_UBLAS_TRIVIAL_STORAGE(T)                                                                        \
    template <>                                                                                              \
    inline unbounded_array<T, std::allocator<T>>::unbounded_array(size_type size, const std::allocator<T>& a) \
        : alloc_(a), size_(size) {                                                                           \
        data_ = size_ ? alloc_.allocate(size_) : nullptr;                                                    \
    }                                                                                                        \
    template <>                                                                                              \
    inline void unbounded_array<T, std::allocator<T>>::resize_internal(const size_type size, const T init,   \
                                                                       const bool preserve) {                \
        if (size == size_) return;                                                                           \
        T* const old = data_;                                                                                \
        data_ = size ? alloc_.allocate(size) : nullptr;                                                      \
        if (size && preserve) {                                                                              \
            const size_type kept = std::min(size, size_);                                                    \
            std::copy_n(old, kept, data_);                                                                   \
            std::fill(data_ + kept, data_ + size, init);                                                     \
        }                                                                                                    \
        if (size_) alloc_.deallocate(old, size_);                                                            \
        size_ = size;                                                                                        \
    }

namespace boost::numeric::ublas {
TVID_UBLAS_TRIVIAL_STORAGE(double)
TVID_UBLAS_TRIVIAL_STORAGE(std::size_t)
}  // namespace boost::numeric::ublas

#undef TVID_UBLAS_TRIVIAL_STORAGE

#endif
