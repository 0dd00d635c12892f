# Run as `cmake -DOUT=file.cpp -DFILES="a;b" -P embed.cmake`: writes a C++
# source that holds each file's text, so the stdlib ships inside the binary.
set(body "")
set(entries "")
foreach(f IN LISTS FILES)
  get_filename_component(name ${f} NAME)
  file(READ ${f} text)
  string(MAKE_C_IDENTIFIER ${name} id)
  string(APPEND body "constexpr std::string_view k_${id} = R\"rcxc_embed(${text})rcxc_embed\";\n")
  string(APPEND entries "    {\"${name}\", k_${id}},\n")
endforeach()
file(WRITE ${OUT}.tmp "// Generated from stdlib/ by cmake/embed.cmake. Do not edit.
#include \"stdlib/stdlib.h\"
namespace rcxc::stdlib {
namespace {
${body}
constexpr EmbeddedFile kFiles[] = {
${entries}};
}  // namespace
std::span<const EmbeddedFile> files() { return kFiles; }
}  // namespace rcxc::stdlib
")
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUT}.tmp)
