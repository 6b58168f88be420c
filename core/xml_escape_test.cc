#include "core/xml_escape.h"

#include <gtest/gtest.h>

namespace tpcal {
namespace {

TEST(XmlEscape, EscapesTheFiveMarkupCharactersAndNothingElse) {
  EXPECT_EQ(XmlEscape("a < b & \"c\" > 'd'"), "a &lt; b &amp; &quot;c&quot; &gt; &#39;d&#39;");
  EXPECT_EQ(XmlEscape("E_B(0X)Z 12.5 um, 0.5 deg"), "E_B(0X)Z 12.5 um, 0.5 deg");
  EXPECT_EQ(XmlEscape(""), "");
  EXPECT_EQ(XmlEscape("&amp;"), "&amp;amp;");  // not idempotent: escape once
}

}  // namespace
}  // namespace tpcal
