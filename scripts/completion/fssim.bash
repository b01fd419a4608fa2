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
            --no-plots --sheet --report --save-float --png-depth
            --read-noise --dark-current --full-well --adc-bits --adc-gain
            --restoration --regularization --prior --velocity-distribution" ;;
    spectra) echo "-h --help -o --output -v --velocity --dt --linear --width --height --title" ;;
    code) echo "-h --help" ;;
    generate) echo "-h --help -L --length -v --velocity --dt --seed --analog -o --output" ;;
    analyze)
      echo "-h --help -v --velocity --dt --snr -m --mode --grid --read-noise --dark-current
            --adc-bits --adc-gain --full-well --json --restoration --regularization --prior
            --velocity-distribution" ;;
    optimize)
      echo "-h --help -L --length -v --velocity --dt --snr -m --mode --binary --min-light
            --restarts --iterations --seed --read-noise --dark-current --adc-bits --adc-gain
            --full-well -o --output --restoration --regularization --prior
            --velocity-distribution" ;;
    sweep)
      echo "-h --help -i --input -c --code -m --mode -v --velocity --snr --dt --trials --seed
            --noise --rmse-margin --threads --max-memory -o --output --plot
            --read-noise --dark-current --full-well --adc-bits --adc-gain
            --restoration --regularization --prior --velocity-distribution" ;;
    campaign)
      echo "-h --help -f --file -i --input -c --code -m --mode -v --velocity --restore-velocity
            --snr --dt --trials --seed --noise --rmse-margin --per-trial --threads -o --output
            --shard --figures --no-progress --read-noise --dark-current --full-well --adc-bits
            --adc-gain --restoration --regularization --prior --velocity-distribution
            --skip-unrunnable" ;;
    merge) echo "-h --help -o --output --figures --skip-unrunnable" ;;
    check) echo "-h --help --columns --abs --rel --k-se --junit --predicted" ;;
    table) echo "-h --help --format --columns --digits -o --output" ;;
  esac
}

# _fssim_takes_value OPTION: whether OPTION is followed by a value (every
# option but the flags).
_fssim_takes_value() {
  case $1 in
    -h | --help | --version | --no-plots | --sheet | --report | --save-float | --linear | --analog | --binary) return 1 ;;
    --figures | --no-progress | --per-trial | --predicted | --skip-unrunnable) return 1 ;;
    -*=*) return 1 ;;
    -*) return 0 ;;
  esac
  return 1
}

# _fssim_add WORDS CUR: adds the words of WORDS that start with CUR.
_fssim_add() {
  mapfile -t -O "${#COMPREPLY[@]}" COMPREPLY < <(compgen -W "$1" -- "$2")
}

# _fssim_paths -f|-d CUR: adds the files and directories (-f), or the
# directories (-d), whose path starts with CUR.
_fssim_paths() {
  compopt -o filenames 2>/dev/null
  mapfile -t -O "${#COMPREPLY[@]}" COMPREPLY < <(compgen "$1" -- "$2")
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
      main:spectra | main:code | main:sweep | main:campaign) context=$word ;;
      campaign:merge | campaign:check | campaign:table) context=$word ;;
      code:generate | code:analyze | code:optimize) context=$word ;;
    esac
  done

  # The value of an option.
  case $prev in
    -c | --code)
      _fssim_add "$_fssim_codes" "$cur"
      _fssim_paths -f "$cur"
      return ;;
    -m | --mode)
      _fssim_add "numerical analog" "$cur"
      return ;;
    --noise)
      _fssim_add "poisson aggregated none" "$cur"
      return ;;
    --png-depth)
      _fssim_add "8 16 auto" "$cur"
      return ;;
    --format)
      _fssim_add "markdown latex csv" "$cur"
      return ;;
    --restoration)
      _fssim_add "inverse tikhonov wiener" "$cur"
      return ;;
    --regularization)
      _fssim_add "optimal" "$cur"
      return ;;
    --prior)
      _fssim_add "power-law oracle" "$cur"
      return ;;
    -i | --input | --json | --plot | -f | --file | --junit)
      _fssim_paths -f "$cur"
      return ;;
    -o | --outdir | --output)
      if [[ $context == main || $context == campaign || $context == merge ]]; then
        _fssim_paths -d "$cur"  # --outdir
      else
        _fssim_paths -f "$cur"
      fi
      return ;;
  esac
  if _fssim_takes_value "$prev"; then
    return  # a number, a range or a size: nothing to offer
  fi

  if [[ $cur == -* ]]; then
    _fssim_add "$(_fssim_options "$context")" "$cur"
    return
  fi
  case $context in
    main) _fssim_add "spectra code sweep campaign" "$cur" ;;
    campaign) _fssim_add "merge check table" "$cur" ;;
    merge) _fssim_paths -d "$cur" ;;
    check | table) _fssim_paths -f "$cur" ;;
    code) _fssim_add "generate analyze optimize" "$cur" ;;
    generate) _fssim_add "sinc mip random snapshot accumulation" "$cur" ;;
    analyze | spectra)
      _fssim_add "$_fssim_codes" "$cur"
      _fssim_paths -f "$cur" ;;
  esac
}
complete -F _fssim fssim
