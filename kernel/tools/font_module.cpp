// The labels' fonts, loaded by the command-line tool for a case with labels (st/occt/font_module.h).

#include "st/core/errors.h"
#include "st/occt/font_module.h"
#include "st/occt/occt_text.h"

#include <exception>
#include <string>
#include <vector>

extern "C" int st_fill_label_outlines(std::vector<st::LabelSpec>* labels, std::string* error) {
  try {
    st::fill_label_outlines(*labels);
    return 0;
  } catch (const st::InvalidInput& e) {
    *error = e.what();
    return 1;
  } catch (const std::exception& e) {
    *error = e.what();
    return 2;
  }
}

// Checked against the header's type: the tool calls it through a FillLabelOutlinesEntry.
[[maybe_unused]] static constexpr st::FillLabelOutlinesEntry kEntryHasTheHeadersType = &st_fill_label_outlines;
