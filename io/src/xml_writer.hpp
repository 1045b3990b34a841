#pragma once
// Private to io/src: the one way this program writes XML (the MuJoCo model built from a URDF,
// urdf_model.cpp). Every attribute value goes through xml_attribute_text, so a name or path taken
// from an input file can never close an attribute or an element, open another one or name a
// file to include: `<robot name="&quot;/>&lt;include file=...">` comes out as the text it is.
//
// No library writes XML here: the XML parsers in Debian (expat, libxml2, tinyxml) read it, and
// libxml2's writer would bring a second XML stack for the dozen elements of one model. The
// escaping rule is XML 1.0 section 2.4 and 3.3.3 (attribute-value normalisation).

#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace blendbench::xml_detail {

// `text` as the content of a double-quoted attribute value: & < > " ' as entity references, and
// tab, line feed and carriage return as character references (a parser would otherwise turn them
// into spaces). Throws std::invalid_argument for a character XML 1.0 cannot carry at all (the
// other control characters below U+0020, and NUL): callers refuse such text as bad input first.
std::string xml_attribute_text(std::string_view text);

// Whether `text` can be written as an attribute value (no control character but tab, line feed
// and carriage return).
bool xml_writable(std::string_view text);

// An XML document written element by element, two spaces of indentation per level.
class XmlWriter {
 public:
  using Attributes = std::initializer_list<std::pair<std::string_view, std::string_view>>;

  // <tag a="v" ...> (closed by close()); tag and attribute names are the program's own (asserted
  // to be XML names), values are escaped.
  void open(std::string_view tag, Attributes attributes = {});
  // <tag a="v" .../>
  void leaf(std::string_view tag, Attributes attributes = {});
  // </tag> of the innermost open element.
  void close();
  // The document; every element must be closed.
  [[nodiscard]] std::string text() const;

 private:
  void start(std::string_view tag, Attributes attributes);
  std::string out_;
  std::vector<std::string> open_;
};

}  // namespace blendbench::xml_detail
