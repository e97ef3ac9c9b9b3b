#pragma once
// The labels' fonts as a module of their own (kernel/tools/font_module.cpp), which the command-line
// tool loads only for a case with labels: OpenCASCADE's libraries take some 45 ms to load and link,
// which every run would pay if the tool were linked with them. This header is all the tool and the
// module share; it needs no OpenCASCADE header.

#include "st/guide/label.h"

#include <string>
#include <vector>

namespace st {

/// The module's file name, beside the tool.
inline constexpr const char* kFontModuleFile = "surgical-template-fonts.so";
/// Its entry point (C linkage): fill_label_outlines (st/occt/occt_text.h) on `labels`. Returns 0, or
/// 1 for invalid input and 2 for a geometry error (the font not found or not read), with the
/// message in `error`: no exception crosses the module's border.
inline constexpr const char* kFontModuleEntry = "st_fill_label_outlines";
using FillLabelOutlinesEntry = int (*)(std::vector<LabelSpec>* labels, std::string* error);

} // namespace st
