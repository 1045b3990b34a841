#pragma once
// How the command line writes micrometres: "µm" where the locale's character set is UTF-8
// (LC_ALL, else LC_CTYPE, else LANG names UTF-8 or utf8, as setlocale would pick them), else
// "um", so a terminal without UTF-8 shows no mojibake (docs/units.md).

#include <string>

namespace blendbench {

// True when the first of LC_ALL, LC_CTYPE, LANG that is set and not empty names UTF-8.
bool utf8_locale();

// "µm" or "um" (utf8_locale()).
const char* micrometre_text();

// A text written for files (UTF-8, "µm") as the command line prints it: every "µm" written as
// micrometre_text() says.
std::string terminal_text(std::string text);

}  // namespace blendbench
