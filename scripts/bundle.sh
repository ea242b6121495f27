#!/usr/bin/env bash
# Builds hybridbench (Release) and gathers into one folder (default: bundle/) the binary and every
# shared library it needs that a bare Linux machine with only a GPU driver lacks (the Vulkan
# loader, tinygltf, stb, libcrypto, ...), with a launcher that points the dynamic loader at them.
# Shaders are embedded, so the bundle runs from any directory:
#   scripts/bundle.sh [DIR]   then on the other machine:   DIR/hybridbench devices
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-bundle}"
build="${HYBRIDBENCH_BUILD_DIR:-build}"  # another build folder keeps a Debug build/ untouched
HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" --target hybridbench
rm -rf "$out"
mkdir -p "$out/bin" "$out/lib"
cp "$build/hybridbench" "$out/bin/"
# The C runtime (glibc, libstdc++, libgcc) is on every Linux machine and must match its kernel and
# driver: leave it out. Everything else the binary resolves to is copied.
ldd "$build/hybridbench" | awk '/=> \// {print $3}' | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libdl.so*|libpthread.so*|librt.so*|ld-linux*|libstdc++.so*|libgcc_s.so*) ;;
    *) cp -L "$lib" "$out/lib/" ;;
  esac
done
# NVIDIA's Vulkan ICD (libGLX_nvidia.so.0) needs libglvnd's dispatch library, which a machine with
# only the driver may lack; the launcher's LD_LIBRARY_PATH makes the ICD find these copies.
for lib in libGLdispatch.so.0 libGLX.so.0 libEGL.so.1 libGL.so.1 libOpenGL.so.0; do
  path=$(ldconfig -p | awk -v l="$lib" '$1 == l && /x86-64/ {print $NF; exit}')
  if [ -n "$path" ]; then cp -L "$path" "$out/lib/"; else echo "bundle: $lib not found (install libglvnd0 libglx0 libegl1 libgl1 libopengl0); NVIDIA machines without it will not find their Vulkan driver" >&2; fi
done
cat > "$out/hybridbench" <<'LAUNCH'
#!/usr/bin/env bash
# hybridbench launcher: uses the libraries bundled beside it.
here="$(cd "$(dirname "$(readlink -f "$0")")" && pwd)"
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
# A machine with the NVIDIA driver but no system Vulkan ICD registration: point the loader at it.
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
  for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json; do
    [ -f "$f" ] && export VK_DRIVER_FILES="$f" && break
  done
fi
exec "$here/bin/hybridbench" "$@"
LAUNCH
chmod +x "$out/hybridbench"
echo "bundle: $out ($(du -sh "$out" | cut -f1)): $(ls "$out/lib" | tr '\n' ' ')"
