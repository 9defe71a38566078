// Fixed-size scratch arrays that a declaration leaves unwritten.
#pragma once
#include <type_traits>

namespace ffd::detail {

/// Room for N objects of T that a declaration leaves unwritten: an array of T would be filled
/// with T's default member values first, which for a hot loop's scratch (the box-pair test's
/// clipping polygons, 1.2 kB a pair) costs more than the work. Each element must be written
/// before it is read. Only for implicit-lifetime types, whose objects the storage itself
/// provides (as UnwrittenAllocator, collision/contact.h).
template <class T, int N>
struct Unwritten {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
    alignas(T) unsigned char bytes[sizeof(T) * N];
    T* data() { return reinterpret_cast<T*>(bytes); }
    const T* data() const { return reinterpret_cast<const T*>(bytes); }
    T& operator[](int i) { return data()[i]; }
    const T& operator[](int i) const { return data()[i]; }
};

} // namespace ffd::detail
