#pragma once
// Private to io/src: a check of an XML text before a recursive parser reads it (urdfdom's
// TinyXML descends one stack frame per element, so a URDF nested 10^5 elements deep crashed the
// program, `validate` too). expat reads it first, without recursion and with its own protection
// against entity expansion ("billion laughs"): the text must be well-formed XML 1.0 in UTF-8,
// nest at most max_depth elements and hold at most max_elements.

#include <cstddef>
#include <string>
#include <string_view>

namespace blendbench::xml_detail {

struct XmlLimits {
  int max_depth = 64;               // a URDF nests 5 (robot, link, visual, geometry, mesh)
  std::size_t max_elements = 100000;  // a six-axis URDF has about 100, a humanoid's a few thousand
};

// Throws InputError(file, line, column, "", message) naming `what` ("URDF file") when the text
// is not well-formed (expat's reason), nests deeper or holds more elements than `limits`.
void check_xml(std::string_view text, const std::string& file, const std::string& what, const XmlLimits& limits);

}  // namespace blendbench::xml_detail
