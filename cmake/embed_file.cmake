# cmake -DIN=file -DOUT=file.inc -DSYMBOL=name -DNAMESPACE=ns -P embed_file.cmake
# Writes the file as a raw string literal in chunks (compilers limit one literal's length).
file(READ ${IN} text)
string(LENGTH "${text}" n)
set(out "namespace ${NAMESPACE} {\nextern const std::string_view ${SYMBOL};\nconst std::string_view ${SYMBOL} =\n")
set(chunk 8000)
set(pos 0)
while(pos LESS n)
  string(SUBSTRING "${text}" ${pos} ${chunk} piece)
  string(APPEND out "R\"bouguer_embed(${piece})bouguer_embed\"\n")
  math(EXPR pos "${pos} + ${chunk}")
endwhile()
string(APPEND out ";\n}\n")
file(WRITE ${OUT} "${out}")
