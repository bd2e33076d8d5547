# Included by the build-time embedding scripts (cmake/EmbedKernels.cmake, viewer/embed_assets.cmake):
# lgn_raw_string_literal(TEXT DELIMITER OUT) sets OUT to TEXT as a C++ expression of adjacent raw
# string literals R"DELIMITER(...)DELIMITER", in chunks because some compilers limit the length of
# one literal; "" for empty text.
function(lgn_raw_string_literal text delimiter out_var)
  string(LENGTH "${text}" len)
  set(pieces "")
  set(pos 0)
  while(pos LESS len)
    string(SUBSTRING "${text}" ${pos} 12000 chunk)
    string(APPEND pieces "R\"${delimiter}(${chunk})${delimiter}\" ")
    math(EXPR pos "${pos} + 12000")
  endwhile()
  if(pieces STREQUAL "")
    set(pieces "\"\"")
  endif()
  set(${out_var} "${pieces}" PARENT_SCOPE)
endfunction()
