// mdbrief.option_fields(): the field tables behind MdBrief(**options), train(**options) and
// match()'s options, for introspection (and the tests that walk every option).
#include "bindings.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/geometry/two_view.hpp"
#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "mdbrief/match/matcher.hpp"
#include "option_keywords.hpp"
#include "trainer/train_options.hpp"

namespace mdbrief::python {
namespace {

const char* typeName(FieldType type) {
  switch (type) {
    case FieldType::Integer: return "int";
    case FieldType::Real: return "float";
    case FieldType::Flag: return "bool";
    case FieldType::Text: return "str";
    case FieldType::TextList: return "list";
    case FieldType::Choice: return "choice";
  }
  return "";
}

template <typename Options>
py::list describe(const OptionTable<Options>& table) {
  const Options defaults{};
  py::list out;
  for (const OptionField<Options>& f : table) {
    py::dict d;
    d["keyword"] = f.keyword;
    d["type"] = typeName(f.type);
    d["doc"] = f.doc;
    d["default"] = keywordObject(f.get(defaults));
    if (f.range) {
      const FieldRange r = f.range(defaults);
      d["range"] = py::make_tuple(r.low, r.high, r.lowOpen, r.highOpen, r.multipleOf, r.odd);
      d["range_text"] = r.text(f.type == FieldType::Integer);
    } else {
      d["range"] = py::none();
    }
    d["choices"] = f.choices;
    out.append(d);
  }
  return out;
}

}  // namespace

void bindOptions(py::module_& m) {
  m.def(
      "option_fields",
      [](const std::string& callable) -> py::list {
        if (callable == "MdBrief") return describe(mdBriefKeywords());
        if (callable == "train") return describe(train::trainOptionFields());
        if (callable == "match") return describe(matchOptionFields());
        if (callable == "match_guided") return describe(guidedMatchOptionFields());
        if (callable == "two_view") return describe(twoViewOptionFields());
        if (callable == "refine_matches") return describe(matchRefinementOptionFields());
        throw py::value_error(
            "callable must be one of: MdBrief, train, match, match_guided, two_view, refine_matches, got '" + callable +
            "'");
      },
      py::arg("callable"),
      "The options of MdBrief, train, match, match_guided, two_view (fit_essential, fit_homography,\n"
      "check_known_pose) or refine_matches, in table order: dicts with keyword, type (int, float,\n"
      "bool, str, list, choice), doc, default, range ((low, high, low_open, high_open, multiple_of, odd)\n"
      "of the defaults, or None), range_text and choices.");
}

}  // namespace mdbrief::python
