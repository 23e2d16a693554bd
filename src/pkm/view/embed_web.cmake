# Builds the page template with web/view.css and web/view.js inlined, as a C++ source defining
# pkm::view::kViewPage. Run at build time: cmake -DWEB=dir -DOUT=file -P embed_web.cmake
file(READ ${WEB}/view.html page)
file(READ ${WEB}/view.css style)
file(READ ${WEB}/view.js script)
string(REPLACE "/*@PKM_STYLE@*/" "${style}" page "${page}")
string(REPLACE "/*@PKM_SCRIPT@*/" "${script}" page "${page}")
string(FIND "${page}" ")pkmweb\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "web/ contains the raw string delimiter )pkmweb\"")
endif()
# Raw string literals are split every 16000 characters: compilers limit a single literal.
string(LENGTH "${page}" length)
set(body "")
set(offset 0)
while(offset LESS length)
  string(SUBSTRING "${page}" ${offset} 16000 chunk)
  string(APPEND body "R\"pkmweb(${chunk})pkmweb\"\n")
  math(EXPR offset "${offset} + 16000")
endwhile()
file(WRITE ${OUT} "// Generated from web/ by src/pkm/view/embed_web.cmake: do not edit.\n"
     "#include \"pkm/view/web_assets.hpp\"\n"
     "namespace pkm::view {\n"
     "static const char kPage[] =\n${body};\n"
     "const std::string_view kViewPage(kPage, sizeof kPage - 1);\n"
     "}\n")
