// The XML writer (io/src/xml_writer.hpp) against an independent reader, expat: any text a value
// holds comes back as that text, in the attribute it was written to, and never as markup (an
// element, an attribute, an entity, an include).

#include "xml_writer.hpp"

#include <expat.h>
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/property.hpp"

namespace blendbench::xml_detail {
namespace {

// What expat reads: each element's name and attributes, in document order; `error` is set when
// the text is not well-formed XML.
struct Parsed {
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> elements;
  std::string error;
};

Parsed parse(const std::string& text) {
  Parsed out;
  XML_Parser parser = XML_ParserCreate("UTF-8");
  XML_SetUserData(parser, &out);
  XML_SetStartElementHandler(parser, [](void* data, const XML_Char* name, const XML_Char** attributes) {
    auto& parsed = *static_cast<Parsed*>(data);
    std::map<std::string, std::string> attrs;
    for (int i = 0; attributes[i] != nullptr; i += 2) attrs[attributes[i]] = attributes[i + 1];
    parsed.elements.emplace_back(name, std::move(attrs));
  });
  if (XML_Parse(parser, text.data(), static_cast<int>(text.size()), 1) == XML_STATUS_ERROR) {
    out.error = XML_ErrorString(XML_GetErrorCode(parser));
  }
  XML_ParserFree(parser);
  return out;
}

// Markup a name from a hostile file might hold (issue 42: a URDF robot name that closed the
// model element and included another file).
const char* const kHostile[] = {
    "\"><include file=\"../evil.xml\"/></mujoco><mujoco model=\"",
    "'&amp;<!ENTITY x SYSTEM \"/etc/passwd\">&x;",
    "<![CDATA[ ]]> <!-- --> <?pi?>",
    "a\tb\nc\rd",
    "&#60;&lt;&",
};

TEST(XmlWriter, HostileValuesComeBackAsTextInTheirAttribute) {
  for (const char* value : kHostile) {
    XmlWriter xml;
    xml.open("mujoco", {{"model", value}});
    xml.leaf("joint", {{"name", value}, {"axis", "0 0 1"}});
    xml.close();
    const Parsed p = parse(xml.text());
    ASSERT_TRUE(p.error.empty()) << p.error << "\n" << xml.text();
    ASSERT_EQ(p.elements.size(), 2u) << xml.text();
    EXPECT_EQ(p.elements[0].first, "mujoco");
    EXPECT_EQ(p.elements[0].second.size(), 1u);
    EXPECT_EQ(p.elements[0].second.at("model"), value);
    EXPECT_EQ(p.elements[1].first, "joint");
    EXPECT_EQ(p.elements[1].second.at("name"), value);
    EXPECT_EQ(p.elements[1].second.at("axis"), "0 0 1");
  }
}

TEST(XmlWriter, RandomTextRoundTripsThroughAnIndependentParser) {
  // every printable ASCII character, the three white-space controls and multi-byte UTF-8
  const std::vector<std::string> pieces = {"<", ">", "&", "\"", "'", "\t", "\n", "\r", " ", "a", "Z", "0", "=", "/",
                                           "!", "?", "[", "]", ";", "#", "\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80"};
  const int cases = test::property_cases(2000);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 4200000 + static_cast<std::uint64_t>(c);
    std::mt19937_64 rng = test::make_rng(seed);
    std::string value;
    const int n = std::uniform_int_distribution<int>(0, 40)(rng);
    for (int i = 0; i < n; ++i) value += pieces[std::uniform_int_distribution<std::size_t>(0, pieces.size() - 1)(rng)];
    XmlWriter xml;
    xml.open("a", {{"v", value}});
    xml.open("b");
    xml.leaf("c", {{"w", value}, {"x", "1"}});
    xml.close();
    xml.close();
    const Parsed p = parse(xml.text());
    ASSERT_TRUE(p.error.empty()) << test::seed_text(seed) << ": " << p.error;
    ASSERT_EQ(p.elements.size(), 3u) << test::seed_text(seed);
    EXPECT_EQ(p.elements[0].second.at("v"), value) << test::seed_text(seed);
    EXPECT_EQ(p.elements[2].second.at("w"), value) << test::seed_text(seed);
    EXPECT_EQ(p.elements[2].second.size(), 2u) << test::seed_text(seed);
  }
}

TEST(XmlWriter, ControlCharactersXmlCannotCarryAreRefused) {
  EXPECT_TRUE(xml_writable("tab\there"));
  for (const char c : {'\0', '\x01', '\x1b', '\x1f'}) {
    const std::string value = std::string("a") + c + "b";
    EXPECT_FALSE(xml_writable(value));
    EXPECT_THROW((void)xml_attribute_text(value), std::invalid_argument);
  }
}

}  // namespace
}  // namespace blendbench::xml_detail
