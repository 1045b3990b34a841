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

std::string terminal_text(std::string text) {
  const std::string micro = "\xC2\xB5m", shown = micrometre_text();
  if (shown == micro) return text;
  for (std::size_t at = text.find(micro); at != std::string::npos; at = text.find(micro, at + shown.size()))
    text.replace(at, micro.size(), shown);
  return text;
}

}  // namespace blendbench
