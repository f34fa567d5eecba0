# Turns the dashboard's files (web/) into a C source of byte arrays that sphd serves
# (server/sphd_http.c): nothing is read from disk or fetched at run time.
# cmake -DDIR=web -DOUT=sphd_web_files.c -DFILES=index.html,app.js,... -P embed_web.cmake
string(REPLACE "," ";" FILES "${FILES}")
set(src "/* generated from web/ by cmake/embed_web.cmake: do not edit */\n#include \"sphd_web.h\"\n\n")
set(table "")
set(i 0)
foreach(f ${FILES})
  file(READ "${DIR}/${f}" hex HEX)
  string(LENGTH "${hex}" n)
  math(EXPR len "${n} / 2")
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
  string(APPEND src "static const unsigned char f${i}[] = {${bytes}0};\n")
  string(APPEND table "    {\"/${f}\", f${i}, ${len}},\n")
  math(EXPR i "${i} + 1")
endforeach()
string(APPEND src "\nconst sphd_web_file sphd_web_files[] = {\n${table}    {0, 0, 0}};\n")
file(WRITE "${OUT}" "${src}")
