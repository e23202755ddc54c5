# Sourced by the benchmarks that run CuraEngine: sets cura_resources to a folder holding
# Cura's JSON machine definitions and exports CURA_ENGINE_SEARCH_PATH. Debian ships them only
# in the GUI package `cura` (416 packages with Qt); instead of installing it, this fetches that
# one .deb with `apt-get download cura` and unpacks its definitions into
# ${XDG_CACHE_HOME:-~/.cache}/mahost/cura-4.13 (once). Needs $work, a scratch folder.
cura_resources=""
for dir in /usr/share/cura/resources "${XDG_CACHE_HOME:-$HOME/.cache}/mahost/cura-4.13/resources"; do
  [[ -f $dir/definitions/fdmprinter.def.json ]] && { cura_resources=$dir; break; }
done
if [[ -z $cura_resources ]]; then
  cache=${XDG_CACHE_HOME:-$HOME/.cache}/mahost/cura-4.13
  echo "fetching Cura's machine definitions (apt-get download cura, once)" >&2
  (cd "$work" && apt-get download cura >/dev/null 2>&1) ||
    { echo "apt-get download cura failed; install the package cura instead" >&2; exit 2; }
  dpkg-deb -x "$work"/cura_*.deb "$work/cura"
  mkdir -p "$cache/resources"
  cp -r "$work/cura/usr/share/cura/resources/definitions" "$work/cura/usr/share/cura/resources/extruders" \
    "$cache/resources/"
  cura_resources=$cache/resources
fi
export CURA_ENGINE_SEARCH_PATH=$cura_resources/definitions:$cura_resources/extruders
