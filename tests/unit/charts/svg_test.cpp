// SPDX-License-Identifier: Apache-2.0
// The svg layer: escaping for any caller's text, numbers without locale, path data, the writer.
#include "ncqual/charts/svg.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <locale>
#include <sstream>
#include <string>

namespace svg = ncqual::charts::svg;

namespace {

const std::string kReplacement = "\xEF\xBF\xBD";

TEST(Svg, EscapesTheFiveMarkupCharacters) {
  EXPECT_EQ(svg::escape("<&\"'>"), "&lt;&amp;&quot;&#39;&gt;");
  EXPECT_EQ(svg::escape("a < b && c"), "a &lt; b &amp;&amp; c");
  // Already escaped text is escaped again: the writer's callers pass plain text.
  EXPECT_EQ(svg::escape("&amp;"), "&amp;amp;");
}

TEST(Svg, KeepsUtf8AndWhitespaceButReplacesWhatXmlForbids) {
  EXPECT_EQ(svg::escape("µm ± 2s ↑ °"), "µm ± 2s ↑ °");
  EXPECT_EQ(svg::escape("a\tb\nc\rd"), "a\tb\nc\rd");
  EXPECT_EQ(svg::escape(std::string("a\x01"
                                    "b")),
            "a" + kReplacement + "b");
  EXPECT_EQ(svg::escape(std::string("x\0y", 3)), "x" + kReplacement + "y");
  // A byte that starts no UTF-8 sequence, a truncated sequence, an overlong '/', a surrogate.
  EXPECT_EQ(svg::escape("\xff"), kReplacement);
  EXPECT_EQ(svg::escape("\xC3"), kReplacement);
  EXPECT_EQ(svg::escape("\xC0\xAF"), kReplacement + kReplacement);
  EXPECT_EQ(svg::escape("\xED\xA0\x80"), kReplacement + kReplacement + kReplacement);
}

TEST(Svg, FixedHasExactlyTheDecimalsAndNoNegativeZero) {
  EXPECT_EQ(svg::fixed(1234.5678, 2), "1234.57");
  EXPECT_EQ(svg::fixed(-2.5e-7, 9), "-0.000000250");
  EXPECT_EQ(svg::fixed(3, 0), "3");
  EXPECT_EQ(svg::fixed(0.1, 3), "0.100");
  EXPECT_EQ(svg::fixed(-0.004, 2), "0.00");
  EXPECT_EQ(svg::fixed(-0.0, 1), "0.0");
  EXPECT_EQ(svg::fixed(std::numeric_limits<double>::quiet_NaN(), 2), "0.00");
  EXPECT_EQ(svg::coord(-12.345678), "-12.35");
}

// A locale whose decimal point is a comma, as a German desktop's would be.
struct CommaDecimal : std::numpunct<char> {
  char do_decimal_point() const override { return ','; }
};

TEST(Svg, NumbersIgnoreTheGlobalLocale) {
  const std::locale before =
      std::locale::global(std::locale(std::locale::classic(), new CommaDecimal));
  std::ostringstream stream;
  stream << 1.5;
  const std::string with_locale = stream.str();
  const std::string fixed = svg::fixed(1.5, 1);
  const std::string exact = svg::exact(1.5);
  std::locale::global(before);
  EXPECT_EQ(with_locale, "1,5");  // the locale took effect for iostreams...
  EXPECT_EQ(fixed, "1.5");        // ...and not for the charts' numbers
  EXPECT_EQ(exact, "1.5");
}

TEST(Svg, ExactReadsBackAsTheSameDouble) {
  EXPECT_EQ(svg::exact(0.1), "0.1");
  EXPECT_EQ(svg::exact(0.0125), "0.0125");
  EXPECT_EQ(svg::exact(-3), "-3");
  EXPECT_EQ(svg::exact(std::numeric_limits<double>::infinity()), "inf");
  for (const double v : {0.1 + 0.2, 1.0 / 3, -1e-300, 6.02214076e23, 0.0104999999}) {
    EXPECT_EQ(std::stod(svg::exact(v)), v) << svg::exact(v);
  }
}

TEST(Svg, TypographicMinusOnlyBeforeNumbers) {
  EXPECT_EQ(svg::typographic_minus("-5"),
            "\xE2\x88\x92"
            "5");
  EXPECT_EQ(svg::typographic_minus("-0.5 to -.5"),
            "\xE2\x88\x92"
            "0.5 to \xE2\x88\x92.5");
  EXPECT_EQ(svg::typographic_minus("pre-cal - x"), "pre-cal - x");
}

TEST(Svg, PathDataIsAbsoluteWithTwoDecimals) {
  svg::Path p;
  EXPECT_TRUE(p.empty());
  p.move_to(1, 2).line_to(3.5, -4).close().move_to(0.004, 0).arc_to(5, false, true, 10, 0);
  EXPECT_EQ(p.str(), "M1.00 2.00 L3.50 -4.00 Z M0.00 0.00 A5.00 5.00 0 0 1 10.00 0.00");
}

TEST(Svg, WriterEscapesAttributesAndTextAndLeavesOutEmptyAttributes) {
  svg::Writer w;
  w.open("g", {{"class", "a\"b"}, {"data-empty", ""}});
  w.leaf("line", {{"x1", "1"}, {"stroke-dasharray", ""}});
  w.text("text", {{"x", "2"}}, "<&>");
  w.close("g");
  EXPECT_EQ(w.str(),
            "<g class=\"a&quot;b\">\n<line x1=\"1\"/>\n<text x=\"2\">&lt;&amp;&gt;</text>\n</g>\n");
}

}  // namespace
