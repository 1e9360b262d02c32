// A value or an error message: how modules return failures without
// exceptions crossing their boundaries.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace ldae {

struct Error {
  std::string message;
};

template <typename T> class Expected {
public:
  Expected(T value) : v_(std::move(value)) {}
  Expected(Error err) : v_(std::move(err)) {}

  explicit operator bool() const { return v_.index() == 0; }
  T &operator*() { assert(*this); return std::get<0>(v_); }
  const T &operator*() const { assert(*this); return std::get<0>(v_); }
  T *operator->() { return &**this; }
  const T *operator->() const { return &**this; }
  const std::string &error() const { assert(!*this); return std::get<1>(v_).message; }

private:
  std::variant<T, Error> v_;
};

} // namespace ldae
