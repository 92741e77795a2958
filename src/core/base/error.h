// Result type for I/O and parsing: a value or a one-line message naming file, line/field and problem.
#pragma once
#include <string>
#include <utility>
#include <variant>

namespace frameless {

struct Error {
  std::string message;  // "FILE:LINE: FIELD: what is wrong" (one line)
};

template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}
  Result(Error error) : v_(std::move(error)) {}
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<0>(v_); }
  const T& value() const { return std::get<0>(v_); }
  T& operator*() { return value(); }
  T* operator->() { return &value(); }
  const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// Keeps a message on one line whatever the input quoted in it holds: line breaks become the
// escapes \n and \r (file names and JSON strings may contain them).
inline std::string one_line(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else out += c;
  }
  return out;
}

template <class T>
Result<T> one_line(Result<T>&& r) {
  if (r.ok()) return std::move(r);
  return Error{one_line(r.error().message)};
}

}  // namespace frameless
