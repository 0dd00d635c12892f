" Vim compiler file: rcxc, the NQC compiler for the LEGO RCX (docs/editors.md).
" :make compiles the current file; errors land in the quickfix list.
if exists("current_compiler")
  finish
endif
let current_compiler = "rcxc"

if exists(":CompilerSet") != 2
  command -nargs=* CompilerSet setlocal <args>
endif

" rcxc compile prints `file:line:col: error: message` (then the source line
" and a caret, which are skipped); an error without a position still names
" the file; `rcxc test` reports failed expectations as `file:line: error:`.
CompilerSet makeprg=rcxc\ compile\ %:S
CompilerSet errorformat=%f:%l:%c:\ %trror:\ %m,
      \%f:%l:%c:\ %tarning:\ %m,
      \%f:%l:%c:\ %tote:\ %m,
      \%f:%l:\ %trror:\ %m,
      \%f:\ %trror:\ %m,
      \%-G%.%#
