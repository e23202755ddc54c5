// A hash table of item numbers whose keys live elsewhere: `key_of(number)` gives an item's
// key, from the caller's own array of items. Open addressing with linear probing and no
// erase: one flat array of 4 bytes a slot instead of a heap node per key, for the corners,
// facets and edges of a mesh and the chain ends of slab and section boundaries. Kept that
// small on purpose: the fresh pages a larger table touches cost more time than its hashing
// saves. `Hash` must spread a key over the low bits (the table indexes by them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace geometry {

template <typename Key, typename Hash>
class NumberTable {
 public:
  static constexpr std::uint32_t kNone = UINT32_MAX;  // no item with that key

  // Room for `expected` items without growing.
  explicit NumberTable(std::size_t expected) { resize(expected); }

  // The number of the item with `key`; if there is none, `number` is stored as that item
  // and returned. key_of must give the key of every number stored so far.
  template <typename KeyOf>
  std::uint32_t find_or_insert(const Key& key, std::uint32_t number, const KeyOf& key_of) {
    if (2 * (size_ + 1) > slots_.size()) {
      std::vector<std::uint32_t> old = std::move(slots_);
      resize(size_ + 1);
      for (std::uint32_t n : old) {
        if (n != kNone) place(key_of(n), n, key_of);
      }
    }
    return place(key, number, key_of);
  }

  // The number of the item with `key`, or kNone.
  template <typename KeyOf>
  std::uint32_t find(const Key& key, const KeyOf& key_of) const {
    for (std::size_t i = Hash{}(key) & mask_;; i = (i + 1) & mask_) {
      if (slots_[i] == kNone || key_of(slots_[i]) == key) return slots_[i];
    }
  }

 private:
  template <typename KeyOf>
  std::uint32_t place(const Key& key, std::uint32_t number, const KeyOf& key_of) {
    for (std::size_t i = Hash{}(key) & mask_;; i = (i + 1) & mask_) {
      if (slots_[i] == kNone) {
        slots_[i] = number;
        ++size_;
        return number;
      }
      if (key_of(slots_[i]) == key) return slots_[i];
    }
  }

  // Room for `count` items at most half full, all slots empty.
  void resize(std::size_t count) {
    std::size_t capacity = 16;
    while (capacity < 2 * count) capacity *= 2;
    slots_.assign(capacity, kNone);
    mask_ = capacity - 1;
    size_ = 0;
  }

  std::vector<std::uint32_t> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace geometry
