// yade-flex kernel: fixed-capacity scratch storage whose slots are constructed only when written
// (GPL-2.0-or-later).
//
// A search's lists (the members of an ownership cluster, the pairs it met) have room for the
// largest case but use a few slots: a plain array of N objects with default member initialisers
// constructs all N on every call, which costs more than the search itself. Here a slot is
// constructed by put() and may be read only after that.
#pragma once
#include <new>
#include <type_traits>

namespace flex {

template <class T, int N> class SlotArray {
	static_assert(std::is_trivially_destructible<T>::value, "SlotArray never destroys its slots");

public:
	SlotArray() { }
	SlotArray(const SlotArray&)            = delete;
	SlotArray& operator=(const SlotArray&) = delete;
	/// Constructs slot i (0 <= i < N) as a copy of v, over whatever it held.
	T& put(int i, const T& v) { return *::new (static_cast<void*>(raw_ + i * sizeof(T))) T(v); }
	/// Slot i, written by put() before.
	T&       operator[](int i) { return *std::launder(reinterpret_cast<T*>(raw_ + i * sizeof(T))); }
	const T& operator[](int i) const { return *std::launder(reinterpret_cast<const T*>(raw_ + i * sizeof(T))); }

private:
	alignas(T) unsigned char raw_[N * sizeof(T)];
};

} // namespace flex
