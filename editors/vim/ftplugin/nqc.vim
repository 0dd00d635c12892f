" NQC buffers: C-like editing, rcxc as the compiler (docs/editors.md).
if exists("b:did_ftplugin")
  finish
endif
let b:did_ftplugin = 1

setlocal commentstring=//\ %s
setlocal comments=s1:/*,mb:*,ex:*/,://
setlocal cindent
setlocal suffixesadd=.nqh
compiler rcxc

" :RcxcRun runs the program on rcxc's emulator, :RcxcTest checks its
" // @expect lines, :RcxcDownload sends it to the brick; :make compiles.
command! -buffer RcxcRun      botright terminal rcxc run %
command! -buffer RcxcTest     let s:mp = &l:makeprg | let &l:makeprg = 'rcxc test %:S' | make | let &l:makeprg = s:mp
command! -buffer RcxcDownload botright terminal rcxc download % --run

" :RcxcFormat lays the buffer out as `rcxc format` does (docs/format.md). A
" filter (:%!) would put rcxc's refusal into the buffer, so the text is only
" replaced when rcxc succeeded.
if !exists('*s:RcxcFormat')
  function s:RcxcFormat() abort
    let l:out = system('rcxc format -', getline(1, '$'))
    if v:shell_error
      echohl ErrorMsg | echomsg substitute(l:out, '\n\+$', '', '') | echohl None
      return
    endif
    let l:lines = split(l:out, "\n", 1)
    if !empty(l:lines) && l:lines[-1] ==# ''
      call remove(l:lines, -1)
    endif
    if l:lines ==# getline(1, '$')
      return
    endif
    let l:view = winsaveview()
    call setline(1, l:lines)
    if line('$') > len(l:lines)
      silent execute (len(l:lines) + 1) . ',$delete _'
    endif
    call winrestview(l:view)
  endfunction
endif
command! -buffer RcxcFormat   call s:RcxcFormat()

let b:undo_ftplugin = "setlocal commentstring< comments< cindent< suffixesadd< makeprg< errorformat<"
      \ . " | delcommand RcxcRun | delcommand RcxcTest | delcommand RcxcDownload | delcommand RcxcFormat"
