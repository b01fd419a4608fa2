// Private helpers for text that reaches a picture or a page.
#pragma once

#include <string>
#include <string_view>

namespace fss::detail {

// `text` with every byte that is not part of a well-formed UTF-8 sequence,
// and every control character, replaced by U+FFFD.
std::string sanitize_utf8(std::string_view text);

// The last component of a path ("codes/x.txt" -> "x.txt"); `text` itself when
// it has no '/'.
std::string_view base_name(std::string_view text);

// `text` for the text or a quoted attribute of an HTML or XML document: & < >
// and " as entities, and ' as &#39; when `apostrophe` is true.
std::string escape_markup(std::string_view text, bool apostrophe);

}  // namespace fss::detail
