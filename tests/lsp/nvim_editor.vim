" Loads editors/vim in headless Neovim (or Vim) for tests/lsp/editors_test.cpp:
" filetype detection, the syntax, and :make with the errorformat on a program
" with an error. g:nqc_file, g:rcxc, g:api_line/g:api_col and g:out are set
" by the test; the findings go to g:out as JSON.
let s:out = {}
try
  execute 'edit ' . fnameescape(g:nqc_file)
  let s:out.filetype = &filetype
  let s:out.syntax = get(b:, 'current_syntax', '')
  let s:out.makeprg = &l:makeprg
  let s:out.commentstring = &l:commentstring
  let s:out.api_group = synIDattr(synID(g:api_line, g:api_col, 1), 'name')
  let &l:makeprg = g:rcxc . ' compile %:S -o /dev/null'
  silent make!
  let s:out.qf = []
  for e in getqflist()
    call add(s:out.qf, {'lnum': e.lnum, 'col': e.col, 'type': e.type, 'text': e.text, 'valid': e.valid,
          \ 'file': fnamemodify(bufname(e.bufnr), ':p')})
  endfor
  let s:out.errmsg = v:errmsg
catch
  let s:out.exception = v:exception . ' at ' . v:throwpoint
endtry
call writefile([json_encode(s:out)], g:out)
qall!
