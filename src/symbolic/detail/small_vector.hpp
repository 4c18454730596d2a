#pragma once
// A vector that keeps its first N elements inline, for the scratch lists of
// the engine's hottest functions (the operands of a sum or product being
// built, the factors of a match).
//
// Why: most sums and products have a handful of operands, and each smart
// constructor used to allocate two or three std::vectors for them; the
// allocations and frees cost more than the canonicalization itself. Past N
// elements the storage moves to the heap, as a std::vector's would.
//
// Only for trivially copyable elements (Expr, Number, plain structs of them):
// growing, copying and moving are memcpy and nothing needs destroying.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <span>
#include <type_traits>

namespace symdyn::symbolic::detail {

template <class T, std::size_t N>
class SmallVector {
  static_assert(std::is_trivially_copyable_v<T>,
                "SmallVector holds trivially copyable elements only");

 public:
  SmallVector() = default;
  SmallVector(std::initializer_list<T> values) { assign(values.begin(), values.size()); }
  ~SmallVector() { release(); }
  SmallVector(const SmallVector& other) { assign(other.data_, other.size_); }
  SmallVector& operator=(const SmallVector& other) {
    if (this != &other) {
      size_ = 0;
      assign(other.data_, other.size_);
    }
    return *this;
  }
  // Moving takes the heap storage, or copies the inline elements; the source is left empty.
  SmallVector(SmallVector&& other) noexcept { take(other); }
  SmallVector& operator=(SmallVector&& other) noexcept {
    if (this != &other) {
      release();
      data_ = inline_data();
      size_ = 0;
      capacity_ = N;
      take(other);
    }
    return *this;
  }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  T& back() { return data_[size_ - 1]; }
  operator std::span<const T>() const {
    return {data_, size_};
  }  // NOLINT(google-explicit-constructor)

  void reserve(std::size_t n) {
    if (n > capacity_) grow(n);
  }
  void push_back(const T& value) {
    if (size_ == capacity_) grow(2 * capacity_);
    data_[size_++] = value;
  }
  void clear() { size_ = 0; }
  // Keeps the first n elements (n <= size()).
  void truncate(std::size_t n) { size_ = n; }
  // Inserts `value` before `position`, shifting the later ones up.
  void insert(T* position, const T& value) {
    const auto at = static_cast<std::size_t>(position - data_);
    const T copy = value;  // `value` may live in this vector
    if (size_ == capacity_) grow(2 * capacity_);
    std::memmove(static_cast<void*>(data_ + at + 1), static_cast<const void*>(data_ + at),
                 (size_ - at) * sizeof(T));
    data_[at] = copy;
    ++size_;
  }
  // Removes the element at `position`, shifting the later ones down.
  void erase(T* position) {
    std::memmove(static_cast<void*>(position), static_cast<const void*>(position + 1),
                 static_cast<std::size_t>(end() - position - 1) * sizeof(T));
    --size_;
  }

  friend bool operator==(const SmallVector& a, const SmallVector& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

 private:
  T* inline_data() { return reinterpret_cast<T*>(inline_); }

  void assign(const T* values, std::size_t n) {
    reserve(n);
    if (n > 0)
      std::memcpy(static_cast<void*>(data_), static_cast<const void*>(values), n * sizeof(T));
    size_ = n;
  }

  void take(SmallVector& other) {
    if (other.data_ == other.inline_data()) {
      assign(other.data_, other.size_);
    } else {
      data_ = other.data_;
      size_ = other.size_;
      capacity_ = other.capacity_;
      other.data_ = other.inline_data();
      other.capacity_ = N;
    }
    other.size_ = 0;
  }

  void release() {
    if (data_ != inline_data()) std::allocator<T>().deallocate(data_, capacity_);
  }

  // Elements are trivially copyable: storage from std::allocator holds them
  // as soon as their bytes are copied in.
  void grow(std::size_t n) {
    T* bigger = std::allocator<T>().allocate(n);
    std::memcpy(static_cast<void*>(bigger), static_cast<const void*>(data_), size_ * sizeof(T));
    if (data_ != inline_data()) std::allocator<T>().deallocate(data_, capacity_);
    data_ = bigger;
    capacity_ = n;
  }

  alignas(T) unsigned char inline_[N * sizeof(T)];
  T* data_ = inline_data();
  std::size_t size_ = 0;
  std::size_t capacity_ = N;
};

}  // namespace symdyn::symbolic::detail
