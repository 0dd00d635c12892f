" NQC sources and headers (rcxc, docs/editors.md).
autocmd BufRead,BufNewFile *.nqc,*.nqh setfiletype nqc
