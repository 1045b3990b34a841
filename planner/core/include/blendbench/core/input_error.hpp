#pragma once
// The one exception type for bad input (a file, a field, a parameter). It is thrown at entry
// points (loaders, validators) and caught only by main(), which prints what() and exits 2.

#include <stdexcept>
#include <string>

namespace blendbench {

class InputError : public std::runtime_error {
 public:
  // `file` may be empty for input that did not come from a file (a command-line flag);
  // `line`/`column` are 1-based, 0 when unknown; `field` names the key, word or flag. what()
  // and detail() are printable on one line (format.hpp printable: control characters and bytes
  // that are not UTF-8 escaped); file() and field() are kept as given.
  InputError(std::string file, int line, int column, std::string field, const std::string& message);

  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] int line() const { return line_; }
  [[nodiscard]] int column() const { return column_; }
  [[nodiscard]] const std::string& field() const { return field_; }
  // The message without the location prefix (printable, as in what()).
  [[nodiscard]] const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  int line_;
  int column_;
  std::string field_;
  std::string detail_;
};

// Where a move or value came from, carried along so later stages can name it in errors.
struct SourceRef {
  std::string file;
  int line = 0;    // 1-based, 0 when unknown
  int column = 0;  // 1-based, 0 when unknown
};

// Throws InputError located at `where`.
[[noreturn]] void fail_at(const SourceRef& where, const std::string& field, const std::string& message);

// The one way an exception a library raised while reading or checking input (std::filesystem,
// nlohmann::json, yaml-cpp, urdfdom, a std::length_error of a size the input asked for) becomes
// bad input: called in a catch block at an input's entry point, it throws InputError located at
// `where`, naming `field`, with `context` and the library's message made printable. An InputError
// passes unchanged, and so do what is not the input's fault: std::bad_alloc, Interrupted (not a
// std::exception) and anything else that is not a std::exception.
[[noreturn]] void rethrow_as_input_error(const SourceRef& where, const std::string& field, const std::string& context);

}  // namespace blendbench
