#!/usr/bin/env bash
# The step of action.yml: install urdftool, check the inputs into a SARIF file, report.
#
# Inputs (environment): URDFTOOL_PATHS (default "."), URDFTOOL_ARGS (extra options, split on
# spaces), URDFTOOL_SARIF (default urdftool.sarif), URDFTOOL_FAIL_ON_FINDINGS (default true),
# URDFTOOL_VERSION (a released version to install; default: the action's own checkout),
# URDFTOOL_EXTRAS (e.g. "meshes"), URDFTOOL_SKIP_INSTALL=1 (use the urdftool on PATH).
# Outputs ($GITHUB_OUTPUT): exit-code, sarif-file.
set -euo pipefail

paths="${URDFTOOL_PATHS:-.}"
sarif="${URDFTOOL_SARIF:-urdftool.sarif}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if [[ "${URDFTOOL_SKIP_INSTALL:-0}" != "1" ]]; then
  extras="${URDFTOOL_EXTRAS:+[${URDFTOOL_EXTRAS}]}"
  if [[ -n "${URDFTOOL_VERSION:-}" ]]; then
    python -m pip install --disable-pip-version-check -q "urdftool${extras}==${URDFTOOL_VERSION}"
  else
    python -m pip install --disable-pip-version-check -q "${here}${extras}"
  fi
fi

# shellcheck disable=SC2086  # paths and extra options are word lists on purpose
set +e
urdftool check --format sarif --output-file "$sarif" ${URDFTOOL_ARGS:-} $paths
status=$?
set -e

if [[ -n "${GITHUB_OUTPUT:-}" ]]; then
  {
    echo "exit-code=$status"
    echo "sarif-file=$sarif"
  } >> "$GITHUB_OUTPUT"
fi

if (( status >= 2 )); then
  echo "::error title=urdftool::urdftool could not check the inputs (exit $status)"
  exit "$status"
fi
if (( status == 1 )); then
  echo "urdftool: findings at failing severity; see the code scanning results ($sarif)"
  if [[ "${URDFTOOL_FAIL_ON_FINDINGS:-true}" == "true" ]]; then
    exit 1
  fi
fi
exit 0
