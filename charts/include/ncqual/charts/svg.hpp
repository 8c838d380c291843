// SPDX-License-Identifier: Apache-2.0
// The SVG layer under every chart: XML escaping, numbers without locale, path data and a small
// writer of elements. Nothing here knows about charts; the charts only ever write through it, so
// that every text is escaped and every number is formatted the same way.
#pragma once

#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::charts::svg {

// `text` fit for XML character data and attribute values (either quote): & < > " ' escaped as
// entities; characters XML 1.0 forbids (C0 controls other than tab, newline and carriage return)
// and bytes that are not UTF-8 replaced with U+FFFD, so that any caller's label gives a
// well-formed document.
std::string escape(std::string_view text);

// `v` with exactly `decimals` digits after the point (0..12), '.' as the decimal point whatever
// the locale, never "-0.00"; "0" style zero for non-finite values (callers skip those first).
std::string fixed(double v, int decimals);

// A coordinate as written into SVG attributes and path data: fixed(v, 2).
std::string coord(double v);

// The shortest text that reads back as exactly `v` ("0.0125", "1e-07"), for data-* attributes;
// "nan", "inf", "-inf" for non-finite values.
std::string exact(double v);

// `text` with an ASCII '-' in front of a digit turned into U+2212 (the minus sign), for labels.
std::string typographic_minus(std::string text);

// SVG path data: absolute commands, coordinates with two decimals.
class Path {
 public:
  Path& move_to(double x, double y);
  Path& line_to(double x, double y);
  // An arc of radius r (circle) to (x, y), the small arc, counter-clockwise on screen when
  // `sweep` is false.
  Path& arc_to(double r, bool large_arc, bool sweep, double x, double y);
  Path& close();
  // The next vertex of a polyline: move_to for the first point of the path, line_to after it.
  Path& vertex(double x, double y) { return empty() ? move_to(x, y) : line_to(x, y); }
  bool empty() const { return d_.empty(); }
  const std::string& str() const { return d_; }

 private:
  std::string d_;
};

// An attribute: name and its value as plain text (the writer escapes it).
using Attr = std::pair<std::string_view, std::string>;

// The attributes of one element, as a braced list at the call ({{"class", "a"}, {"x", "1"}}) or
// a vector built beforehand. A view: it holds neither, so it is only ever a parameter of the
// writer's calls (the list or vector outlives the call).
class Attrs {
 public:
  Attrs() = default;
  Attrs(std::initializer_list<Attr> list) {
    begin_ = list.begin();
    end_ = list.end();
  }
  Attrs(const std::vector<Attr>& list) : begin_(list.data()), end_(list.data() + list.size()) {}
  const Attr* begin() const { return begin_; }
  const Attr* end() const { return end_; }

 private:
  const Attr* begin_ = nullptr;
  const Attr* end_ = nullptr;
};

// Writes elements into one string. Attributes whose value is empty are left out, so optional
// attributes can be passed as "" .
class Writer {
 public:
  // <tag a="v" ...>
  void open(std::string_view tag, Attrs attrs = {});
  // </tag>
  void close(std::string_view tag);
  // <tag a="v" .../>
  void leaf(std::string_view tag, Attrs attrs);
  // <tag a="v" ...>text</tag>, text escaped
  void text(std::string_view tag, Attrs attrs, std::string_view text);
  // Raw markup (already escaped), e.g. another writer's output.
  void raw(std::string_view markup) { out_ += markup; }
  const std::string& str() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  void start(std::string_view tag, Attrs attrs);
  std::string out_;
};

}  // namespace ncqual::charts::svg
