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

let b:undo_ftplugin = "setlocal commentstring< comments< cindent< suffixesadd< makeprg< errorformat<"
      \ . " | delcommand RcxcRun | delcommand RcxcTest | delcommand RcxcDownload"
