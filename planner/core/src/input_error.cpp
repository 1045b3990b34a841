#include "blendbench/core/input_error.hpp"

#include <new>
#include <utility>

#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

// "file:line:column: 'field': message", every part printable (bytes of a binary input, a file
// name or a key with control characters are escaped, so the message stays one line).
std::string format_location(const std::string& file, int line, int column, const std::string& field,
                            const std::string& message) {
  std::string out;
  if (!file.empty()) {
    out += printable(file);
    if (line > 0) {
      out += ':';
      out += std::to_string(line);
      if (column > 0) {
        out += ':';
        out += std::to_string(column);
      }
    }
    out += ": ";
  }
  // appended part by part: "'" + printable(field) built a temporary that GCC 12 warned about
  // (a -Wrestrict false positive on inserting at the front of a string)
  if (!field.empty()) {
    out += '\'';
    out += printable(field);
    out += "': ";
  }
  out += printable(message);
  return out;
}

}  // namespace

InputError::InputError(std::string file, int line, int column, std::string field, const std::string& message)
    : std::runtime_error(format_location(file, line, column, field, message)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      field_(std::move(field)),
      detail_(printable(message)) {}

void fail_at(const SourceRef& where, const std::string& field, const std::string& message) {
  throw InputError(where.file, where.line, where.column, field, message);
}

void rethrow_as_input_error(const SourceRef& where, const std::string& field, const std::string& context) {
  try {
    throw;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(where.file, where.line, where.column, field, context + e.what());
  }
}

}  // namespace blendbench
