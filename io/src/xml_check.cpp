// The XML check before a recursive parser (xml_check.hpp), with expat.

#include "xml_check.hpp"

#include <expat.h>

#include <memory>

#include "blendbench/core/input_error.hpp"

namespace blendbench::xml_detail {
namespace {

struct Walk {
  XML_Parser parser = nullptr;
  XmlLimits limits;
  int depth = 0;
  std::size_t elements = 0;
  std::string problem;  // set when a limit stopped the parse
};

void on_start(void* data, const XML_Char* /*name*/, const XML_Char** /*attributes*/) {
  auto& walk = *static_cast<Walk*>(data);
  ++walk.elements;
  if (++walk.depth > walk.limits.max_depth) {
    walk.problem = "elements are nested more than " + std::to_string(walk.limits.max_depth) + " deep";
  } else if (walk.elements > walk.limits.max_elements) {
    walk.problem = "it holds more than " + std::to_string(walk.limits.max_elements) + " elements";
  }
  if (!walk.problem.empty()) XML_StopParser(walk.parser, XML_FALSE);
}

void on_end(void* data, const XML_Char* /*name*/) { --static_cast<Walk*>(data)->depth; }

}  // namespace

void check_xml(std::string_view text, const std::string& file, const std::string& what, const XmlLimits& limits) {
  const std::unique_ptr<XML_ParserStruct, void (*)(XML_Parser)> parser(XML_ParserCreate("UTF-8"), XML_ParserFree);
  if (!parser) throw InputError(file, 0, 0, "", "cannot start the XML parser (out of memory)");
  Walk walk;
  walk.parser = parser.get();
  walk.limits = limits;
  XML_SetUserData(parser.get(), &walk);
  XML_SetElementHandler(parser.get(), on_start, on_end);
  // in pieces: expat takes an int length
  constexpr std::size_t kPiece = std::size_t{1} << 24;
  std::size_t at = 0;
  XML_Status status = XML_STATUS_OK;
  do {
    const std::size_t n = std::min(kPiece, text.size() - at);
    status = XML_Parse(parser.get(), text.data() + at, static_cast<int>(n), at + n == text.size() ? XML_TRUE : XML_FALSE);
    at += n;
  } while (status == XML_STATUS_OK && at < text.size());
  if (status == XML_STATUS_OK) return;
  const int line = static_cast<int>(XML_GetCurrentLineNumber(parser.get()));
  const int column = static_cast<int>(XML_GetCurrentColumnNumber(parser.get())) + 1;
  if (!walk.problem.empty()) throw InputError(file, line, column, "", "the " + what + " is refused: " + walk.problem);
  throw InputError(file, line, column, "",
                   "the " + what + " is not well-formed XML: " + XML_ErrorString(XML_GetErrorCode(parser.get())));
}

}  // namespace blendbench::xml_detail
