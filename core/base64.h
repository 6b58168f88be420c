// Base64 (RFC 4648 alphabet, XML Schema's base64Binary), for binary arrays inside XML text such
// as QIF's <BinaryPoints>. Written here because none of the project's Debian libraries decodes a
// text span (libxml2 decodes base64 only inside its xmlTextReader API, not its SAX2 parser).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace tpcal {

// The bytes `text` encodes. Blanks (space, tab, CR, LF) anywhere are skipped; '=' padding may
// only end the data. Failure (nullopt, *bad_offset set): the offset in `text` of the first
// character outside the alphabet or misplaced '=', or text.size() when the characters do not
// make whole 4-character groups.
std::optional<std::string> DecodeBase64(std::string_view text, std::size_t* bad_offset);

// `bytes` as base64 with '=' padding and no line breaks.
std::string EncodeBase64(std::string_view bytes);

}  // namespace tpcal
