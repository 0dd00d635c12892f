# Who may include whom: the one statement of the project's layering.
# Each product folder lists the folders of ours its files may #include
# (itself always). tests/, bench/ and fuzz/ sit above everything.
# CheckLayers.cmake reads this list; the `layering` test runs it.
set(RCXC_LAYERS
  "rcx:"
  "tomlfile:"
  "savefile:"
  "runtime:rcx,tomlfile"
  "link:rcx,runtime"
  "stdlib:"
  "frontend:rcx,stdlib"
  "ir:rcx,frontend"
  "backend:rcx,frontend,ir"
  "verify:rcx,runtime,tomlfile"
  "format:rcx,frontend"
  "lsp:stdlib,frontend,ir,backend,format,savefile"
  "dap:rcx,tomlfile,runtime,stdlib,frontend,ir,backend,lsp"
  "nxt:tomlfile"
  "cli:rcx,tomlfile,savefile,runtime,link,stdlib,frontend,format,ir,backend,verify,nxt,lsp,dap,cli")
