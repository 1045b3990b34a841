#include "blendbench/app/unit_text.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace blendbench {

bool utf8_locale() {
  for (const char* name : {"LC_ALL", "LC_CTYPE", "LANG"}) {
    const char* value = std::getenv(name);
    if (value == nullptr || *value == '\0') continue;
    std::string text(value);
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text.find("utf-8") != std::string::npos || text.find("utf8") != std::string::npos;
  }
  return false;
}

const char* micrometre_text() { return utf8_locale() ? "\xC2\xB5m" : "um"; }

}  // namespace blendbench
