# Writes a header that holds the text of a file as a C++ raw string constant.
#   set(INPUT file) set(OUTPUT header) set(NAME kName) include(embed_text.cmake)
file(READ "${INPUT}" text)
file(WRITE "${OUTPUT}.tmp" "#pragma once\n// Generated from ${INPUT}: do not edit.\nnamespace st {\ninline constexpr const char* ${NAME} = R\"st_embed(${text})st_embed\";\n}\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
