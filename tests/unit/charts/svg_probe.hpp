// SPDX-License-Identifier: Apache-2.0
// Reading the charts' output back in tests: the elements of a tag with their attributes, found
// by class. Only for the SVG ncqual_charts writes (attributes in double quotes, no '>' inside
// them, which escape() guarantees).
#pragma once

#include <map>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace ncqual::charts::test {

struct Element {
  std::string tag;
  std::map<std::string, std::string> attrs;
  bool has(const std::string& name) const { return attrs.count(name) > 0; }
  std::string get(const std::string& name) const {
    const auto it = attrs.find(name);
    return it == attrs.end() ? std::string() : it->second;
  }
  double num(const std::string& name) const {
    const auto it = attrs.find(name);
    if (it == attrs.end()) throw std::runtime_error("no attribute " + name + " on <" + tag + ">");
    return std::stod(it->second);
  }
};

// Every <tag ...> (opening or empty) in document order.
inline std::vector<Element> elements(const std::string& svg, const std::string& tag) {
  std::vector<Element> out;
  const std::regex open("<" + tag + "((?:\\s+[A-Za-z_:][-A-Za-z0-9_:.]*=\"[^\"]*\")*)\\s*/?>");
  const std::regex attr("([A-Za-z_:][-A-Za-z0-9_:.]*)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), open); it != std::sregex_iterator();
       ++it) {
    Element e{tag, {}};
    const std::string attrs = (*it)[1];
    for (auto a = std::sregex_iterator(attrs.begin(), attrs.end(), attr);
         a != std::sregex_iterator(); ++a) {
      e.attrs[(*a)[1]] = (*a)[2];
    }
    out.push_back(e);
  }
  return out;
}

// The elements of `tag` whose class attribute is exactly `cls`.
inline std::vector<Element> with_class(const std::string& svg, const std::string& tag,
                                       const std::string& cls) {
  std::vector<Element> out;
  for (const Element& e : elements(svg, tag)) {
    if (e.get("class") == cls) out.push_back(e);
  }
  return out;
}

// The one element of `tag` with class `cls`; throws when there is not exactly one.
inline Element only(const std::string& svg, const std::string& tag, const std::string& cls) {
  const auto all = with_class(svg, tag, cls);
  if (all.size() != 1) {
    throw std::runtime_error(std::to_string(all.size()) + " <" + tag + " class=\"" + cls + "\">");
  }
  return all[0];
}

// The numbers of an SVG path's data, in order ("M1.00 2.00 L3.00 4.00" -> 1, 2, 3, 4).
inline std::vector<double> path_numbers(const std::string& d) {
  std::vector<double> out;
  const std::regex number("-?[0-9]+(?:\\.[0-9]+)?");
  for (auto it = std::sregex_iterator(d.begin(), d.end(), number); it != std::sregex_iterator();
       ++it) {
    out.push_back(std::stod(it->str()));
  }
  return out;
}

// The text between <tag> and </tag> of the first such element (no nesting).
inline std::string first_text(const std::string& svg, const std::string& tag) {
  const auto from = svg.find("<" + tag + ">");
  if (from == std::string::npos) return "";
  const auto start = from + tag.size() + 2;
  return svg.substr(start, svg.find("</" + tag + ">", start) - start);
}

}  // namespace ncqual::charts::test
