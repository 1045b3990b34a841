// Writing XML with every value escaped (xml_writer.hpp).

#include "xml_writer.hpp"

#include <cassert>
#include <stdexcept>

namespace blendbench::xml_detail {
namespace {

// An XML name as this program writes them: ASCII letters, digits, '_', '-', '.', not starting
// with a digit, '-' or '.' (the tags and attribute names are literals of the program).
[[maybe_unused]] bool plain_name(std::string_view name) {
  if (name.empty()) return false;
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!letter(name.front())) return false;
  for (const char c : name) {
    if (!letter(c) && !(c >= '0' && c <= '9') && c != '-' && c != '.') return false;
  }
  return true;
}

}  // namespace

bool xml_writable(std::string_view text) {
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && u != '\t' && u != '\n' && u != '\r') return false;
  }
  return true;
}

std::string xml_attribute_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      case '\t': out += "&#9;"; break;
      case '\n': out += "&#10;"; break;
      case '\r': out += "&#13;"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          throw std::invalid_argument("a control character (code " + std::to_string(static_cast<int>(c)) +
                                      ") cannot be written in XML");
        }
        out += c;
    }
  }
  return out;
}

void XmlWriter::start(std::string_view tag, Attributes attributes) {
  assert(plain_name(tag));
  out_.append(2 * open_.size(), ' ');
  out_ += '<';
  out_ += tag;
  for (const auto& [name, value] : attributes) {
    assert(plain_name(name));
    out_ += ' ';
    out_ += name;
    out_ += "=\"";
    out_ += xml_attribute_text(value);
    out_ += '"';
  }
}

void XmlWriter::open(std::string_view tag, Attributes attributes) {
  start(tag, attributes);
  out_ += ">\n";
  open_.emplace_back(tag);
}

void XmlWriter::leaf(std::string_view tag, Attributes attributes) {
  start(tag, attributes);
  out_ += "/>\n";
}

void XmlWriter::close() {
  assert(!open_.empty());
  const std::string tag = std::move(open_.back());
  open_.pop_back();
  out_.append(2 * open_.size(), ' ');
  out_ += "</" + tag + ">\n";
}

std::string XmlWriter::text() const {
  assert(open_.empty());
  return out_;
}

}  // namespace blendbench::xml_detail
