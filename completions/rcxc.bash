# bash completion for rcxc (installed as share/bash-completion/completions/rcxc).
# The commands and options are those of `rcxc help COMMAND`;
# tests/cli/help_test.cpp checks that none is missing.

_rcxc() {
  local cur prev words cword
  if declare -F _init_completion >/dev/null; then
    _init_completion || return
  else
    cur=${COMP_WORDS[COMP_CWORD]}
    prev=${COMP_WORDS[COMP_CWORD-1]}
    words=("${COMP_WORDS[@]}")
    cword=$COMP_CWORD
  fi

  local commands="compile run disasm test compare brick download remote nxt nqc lsp debug format help version"
  if [[ $cword -eq 1 ]]; then
    COMPREPLY=($(compgen -W "$commands --help --version" -- "$cur"))
    return
  fi

  local command=${words[1]} options="" files=""
  case $command in
    compile)
      options="-o --output -I -D -U -n -E -Werror -Wno- -Werror= -w -O0 -O1 -O2 -Os --listing -v --verbose --diagnostics --max-errors --color --help"
      files="!*.@(nqc|nqh)" ;;
    run)
      options="--scenario --for --seed --report --trace --instruction-us --nxt -I -D -U -n -O0 -O1 -O2 -Os --help"
      files="!*.@(nqc|rcx)" ;;
    disasm)
      options="--help"
      files="!*.rcx" ;;
    test)
      options="--nqc --nqc-path -v --verbose -j --jobs --junit -I -D -U -n -O0 -O1 -O2 -Os --help"
      files="!*.nqc" ;;
    compare)
      options="--scenario --nqc-path --for --seed --instruction-us --all-rows --help"
      files="!*.nqc" ;;
    brick)
      options="--pty --noise --seed --fast --no-echo -v --verbose --help" ;;
    download)
      options="-I --port --program --run --retries --no-sound -v --verbose --help"
      files="!*.@(nqc|rcx)" ;;
    nxt)
      options="--port --json -v --verbose --timeout --help"
      if [[ $COMP_CWORD -eq 2 || $prev != -* ]]; then
        COMPREPLY=($(compgen -W "info battery rename tone motor motor-state motor-reset sensor read ultrasonic mailbox start stop current play stop-sound keepalive volume sleep bluetooth tacho-reset datalog contacts connections modules iomap poll erase-all ls upload download rm raw bench brick $options" -- "$cur"))
        return
      fi ;;
    remote)
      options="--port --csv --retries --help"
      if [[ $cword -eq 2 || ${words[cword-1]} == --* && $cword -eq 3 ]]; then
        COMPREPLY=($(compgen -W "alive versions battery run stop program message get datalog watch sleep clear firmware raw" -- "$cur"))
        return
      fi ;;
    lsp)
      options="-I -D -U -n -Wno- --stdio --stdlib-dir --help" ;;
    debug)
      options="--help" ;;
    format)
      options="-i --in-place --check --indent --help"
      files="!*.@(nqc|nqh)" ;;
    help)
      COMPREPLY=($(compgen -W "$commands" -- "$cur"))
      return ;;
    version)
      return ;;
  esac

  case $prev in
    -I|--stdlib-dir)
      COMPREPLY=($(compgen -d -- "$cur")); return ;;
    --scenario)
      COMPREPLY=($(compgen -f -X '!*.toml' -- "$cur")); return ;;
    -o|--output|--trace|--nqc-path)
      COMPREPLY=($(compgen -f -- "$cur")); return ;;
    --report)
      COMPREPLY=($(compgen -W "json" -- "$cur")); return ;;
    --diagnostics)
      COMPREPLY=($(compgen -W "text json" -- "$cur")); return ;;
    --port)
      COMPREPLY=($(compgen -W "usb serial" -- "$cur") $(compgen -f -- "$cur")); return ;;
    --program)
      COMPREPLY=($(compgen -W "1 2 3 4 5" -- "$cur")); return ;;
    --indent)
      COMPREPLY=($(compgen -W "1 2 3 4 5 6 7 8" -- "$cur")); return ;;
  esac

  if [[ $cur == -* ]]; then
    COMPREPLY=($(compgen -W "$options" -- "$cur"))
  elif [[ -n $files ]]; then
    local IFS=$'\n'
    COMPREPLY=($(shopt -s extglob; compgen -f -X "$files" -- "$cur") $(compgen -d -- "$cur"))
  else
    COMPREPLY=($(compgen -f -- "$cur"))
  fi
}
complete -F _rcxc rcxc
