// The page template with web/'s style and script inlined (generated at build time from web/ by
// embed_web.cmake): markers @PKM_TITLE@ and @PKM_DATA@ remain for the view to fill.
#pragma once

#include <string_view>

namespace pkm::view {
extern const std::string_view kViewPage;
}
