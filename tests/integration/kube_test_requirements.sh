# What the kube tests (kube_fleet_test.sh, kube_sweep_test.sh) need, checked alike. Source it,
# then call: kube_test_require TEST_NAME SOURCE_DIR IMAGE
# Without root, podman, the packages image or a build: a skip (exit 77) that says why; under
# CI=true a failure (exit 1).
kube_test_require() {
  local name=$1 source_dir=$2 image=$3 verdict status
  kube_test_missing() {
    if [[ "${CI:-}" == true ]]; then
      echo "$name: FAILED: $* (CI=true: required)" >&2
      exit 1
    fi
    echo "$name: skipped: $*" >&2
    exit 77
  }
  [[ $(id -u) -eq 0 ]] || kube_test_missing "needs root (podman kube play of pods with NET_ADMIN)"
  if ! command -v podman >/dev/null; then
    # scripts/setup says whether this machine should have it (it installs podman where it can run).
    verdict=$("$source_dir/scripts/setup" --check containers) && status=0 || status=$?
    if ((status == 77)); then echo "$name: skipped: no podman; $verdict" >&2; exit 77; fi
    kube_test_missing "no podman; $verdict"
  fi
  if [[ "${SITLNET_MIN_CAPS:-}" == 1 ]]; then  # the container pass (scripts/container-test)
    echo "$name: skipped: podman needs more than CAP_NET_ADMIN + CAP_SYS_ADMIN" >&2
    exit 77
  fi
  podman image exists "$image" ||
    kube_test_missing "no image $image (sudo scripts/container-test --prepare makes it)"
  [[ -x "$source_dir/build/bin/sitlnet" ]] || kube_test_missing "no build in $source_dir/build (the pods run it)"
}
