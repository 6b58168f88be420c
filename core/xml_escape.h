// Escaping of text for XML and HTML (element text and quoted attribute values): the one escaper
// of the SVG figures, the HTML reports and the G-code backplots.
#pragma once

#include <string>
#include <string_view>

namespace tpcal {

// `text` with & < > " ' replaced by their entities. Never fails.
std::string XmlEscape(std::string_view text);

}  // namespace tpcal
