# bash completion for fssim, the flutter shutter camera simulator.
# Installed as share/bash-completion/completions/fssim; to try it from a
# checkout: source scripts/completion/fssim.bash
# Needs only bash (not the bash-completion package's helpers).

_fssim_codes="snapshot accumulation raskar random mip sinc"

# _fssim_options CONTEXT: the options of a (sub)command.
_fssim_options() {
  case $1 in
    main)
      echo "-h --help --version -i --input -c --code -m --mode -v --velocity --restore-velocity
            --dt --snr --seed --noise --rmse-margin --trials --threads --max-memory -o --outdir
            --no-plots --sheet --report" ;;
    spectra) echo "-h --help -o --output -v --velocity --dt --linear --width --height --title" ;;
    code) echo "-h --help" ;;
    generate) echo "-h --help -L --length -v --velocity --dt --seed --analog -o --output" ;;
    analyze) echo "-h --help -v --velocity --dt --snr -m --mode --grid --json" ;;
    optimize)
      echo "-h --help -L --length -v --velocity --dt --snr -m --mode --binary --min-light
            --restarts --iterations --seed -o --output" ;;
    sweep)
      echo "-h --help -i --input -c --code -m --mode -v --velocity --snr --dt --trials --seed
            --rmse-margin --threads -o --output --plot" ;;
  esac
}

# _fssim_takes_value OPTION: whether OPTION is followed by a value (every
# option but the flags).
_fssim_takes_value() {
  case $1 in
    -h | --help | --version | --no-plots | --sheet | --report | --linear | --analog | --binary) return 1 ;;
    -*=*) return 1 ;;
    -*) return 0 ;;
  esac
  return 1
}

# Adds the files and directories (to walk into) that start with $1.
_fssim_files() {
  local IFS=$'\n'
  compopt -o filenames 2>/dev/null
  COMPREPLY+=($(compgen -f -- "$1"))
}

_fssim() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev=""
  ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
  COMPREPLY=()

  # The (sub)command being completed: walk the words before the cursor,
  # skipping option values.
  local context=main i word
  for ((i = 1; i < COMP_CWORD; i++)); do
    word=${COMP_WORDS[i]}
    if [[ $word == -* ]]; then
      _fssim_takes_value "$word" && ((i++))
      continue
    fi
    case $context:$word in
      main:spectra | main:code | main:sweep) context=$word ;;
      code:generate | code:analyze | code:optimize) context=$word ;;
    esac
  done

  # The value of an option.
  case $prev in
    -c | --code)
      COMPREPLY=($(compgen -W "$_fssim_codes" -- "$cur"))
      _fssim_files "$cur"
      return ;;
    -m | --mode)
      COMPREPLY=($(compgen -W "numerical analog" -- "$cur"))
      return ;;
    --noise)
      COMPREPLY=($(compgen -W "poisson none" -- "$cur"))
      return ;;
    -i | --input | --json | --plot)
      _fssim_files "$cur"
      return ;;
    -o | --outdir | --output)
      if [[ $context == main ]]; then
        local IFS=$'\n'
        compopt -o filenames 2>/dev/null
        COMPREPLY=($(compgen -d -- "$cur"))
      else
        _fssim_files "$cur"
      fi
      return ;;
  esac
  if _fssim_takes_value "$prev"; then
    return  # a number, a range or a size: nothing to offer
  fi

  if [[ $cur == -* ]]; then
    COMPREPLY=($(compgen -W "$(_fssim_options "$context")" -- "$cur"))
    return
  fi
  case $context in
    main) COMPREPLY=($(compgen -W "spectra code sweep" -- "$cur")) ;;
    code) COMPREPLY=($(compgen -W "generate analyze optimize" -- "$cur")) ;;
    generate) COMPREPLY=($(compgen -W "sinc mip random snapshot accumulation" -- "$cur")) ;;
    analyze | spectra)
      COMPREPLY=($(compgen -W "$_fssim_codes" -- "$cur"))
      _fssim_files "$cur" ;;
  esac
}
complete -F _fssim fssim
