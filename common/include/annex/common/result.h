#pragma once
// Expected failures (bad file, bad spec, no plane, lost sensor) travel as values,
// so callers can tell "nothing found" from "misconfigured" and print one clear line.

#include <string>
#include <utility>
#include <variant>

namespace annex {

// Where an error happened: a file (or other origin such as "<stdin>" or "frame 12")
// and a 1-based line and column; 0 means "not applicable".
struct Location {
  std::string origin;
  int line = 0;
  int column = 0;
  bool operator==(const Location&) const = default;
};

struct Error {
  std::string message;
  Location location;

  // "file:line:col: error: message", the form compilers use so editors can jump to it.
  std::string format() const;
  bool operator==(const Error&) const = default;
};

template <typename T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}
  Result(Error error) : v_(std::move(error)) {}

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const Error& error() const { return std::get<1>(v_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, Error> v_;
};

// For operations that only succeed or fail.
struct Ok {};
using Status = Result<Ok>;

}  // namespace annex
