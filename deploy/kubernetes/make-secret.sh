#!/usr/bin/env bash
# Makes the Secret "tessera" of deploy/kubernetes: a CA, one certificate for every pod of the
# worker StatefulSet, and a random token, with deploy/tls/make-certs.sh into DIR (kept: the CA
# and the token are reused when the script runs again, say for another namespace); then prints
# the kubectl command that creates the Secret, or runs it with --apply. docs/farm.md,
# "Kubernetes".
#
#   deploy/kubernetes/make-secret.sh [--namespace NS] [--service NAME] [--apply] DIR
set -euo pipefail
usage() {
  echo "usage: $0 [--namespace NS] [--service NAME] [--apply] DIR" >&2
  exit 2
}
namespace=default
service=tessera-worker
apply=0
while [ $# -gt 0 ]; do
  case "$1" in
    --namespace | -n) [ $# -ge 2 ] || usage; namespace="$2"; shift 2 ;;
    --service) [ $# -ge 2 ] || usage; service="$2"; shift 2 ;;
    --apply) apply=1; shift ;;
    -h | --help) usage ;;
    -*) echo "$0: unknown option $1" >&2; usage ;;
    *) break ;;
  esac
done
[ $# -eq 1 ] || usage
dir="$1"
here="$(cd "$(dirname "$0")" && pwd)"
# deploy/tls beside deploy/kubernetes, in the source tree as in <prefix>/share/tessera/deploy.
# The certificate names the Service, which hosts verify it against (TESSERA_TLS_SERVER_NAME in
# render-job.yaml): gRPC takes no wildcard over a single label (*.tessera-worker would not match
# tessera-worker-0.tessera-worker), and one name serves any number of replicas. The wildcards
# of the namespace's full names serve hosts that address pods by those.
"$here/../tls/make-certs.sh" --label "$service" "$dir" "$service" "*.$service.$namespace.svc" \
  "*.$service.$namespace.svc.cluster.local" >&2
command=(kubectl create secret generic tessera --namespace "$namespace"
  "--from-file=ca.pem=$dir/ca.pem"
  "--from-file=worker.pem=$dir/$service/worker.pem"
  "--from-file=worker.key=$dir/$service/worker.key"
  "--from-file=tessera.token=$dir/tessera.token")
if [ "$apply" -eq 1 ]; then
  "${command[@]}"
else
  printf '%q ' "${command[@]}"
  printf '\n'
fi
