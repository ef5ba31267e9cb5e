#!/usr/bin/env bash
# Makes the TLS material and the token of a Tessera farm with openssl, the steps of
# docs/security.md "Setting up a remote worker" in one command (docs/farm.md).
#
#   deploy/tls/make-certs.sh [--days N] [--label LABEL] DIR NAME [NAME...]
#
# In DIR (created mode 0700; files 0600 but the certificates):
#   ca.pem, ca.key      the CA, made once: kept when DIR has them, so that every worker's
#                       certificate comes from one CA. Keep ca.key off the workers.
#   tessera.token       the token hosts and workers share, made once (kept likewise)
#   LABEL/worker.pem    a certificate for a worker, valid for every NAME (DNS names, wildcards
#   LABEL/worker.key    such as *.tessera-worker, IPv4 and IPv6 addresses); LABEL is the first
#                       NAME without a leading "*."
# A worker takes LABEL/worker.pem, LABEL/worker.key and tessera.token; a host takes ca.pem and
# tessera.token.
set -euo pipefail

usage() {
  echo "usage: $0 [--days N] [--label LABEL] DIR NAME [NAME...]" >&2
  exit 2
}
days=825
label=""
while [ $# -gt 0 ]; do
  case "$1" in
    --days) [ $# -ge 2 ] || usage; days="$2"; shift 2 ;;
    --label) [ $# -ge 2 ] || usage; label="$2"; shift 2 ;;
    -h | --help) usage ;;
    --) shift; break ;;
    -*) echo "$0: unknown option $1" >&2; usage ;;
    *) break ;;
  esac
done
[ $# -ge 2 ] || usage
dir="$1"
shift
command -v openssl >/dev/null || { echo "$0: needs openssl" >&2; exit 1; }
[ -n "$label" ] || label="${1#\*.}"
case "$label" in
  "" | */* | .*) echo "$0: cannot name a directory '$label' (give --label)" >&2; exit 2 ;;
esac

sans=""
for name in "$@"; do
  if [[ "$name" =~ ^[0-9.]+$ || "$name" == *:* ]]; then
    sans+="${sans:+,}IP:$name"
  elif [[ "$name" =~ ^(\*\.)?[A-Za-z0-9]([A-Za-z0-9.-]*[A-Za-z0-9])?$ ]]; then
    sans+="${sans:+,}DNS:$name"
  else
    echo "$0: '$name' is neither a DNS name nor an IP address" >&2
    exit 2
  fi
done

umask 077
mkdir -p "$dir/$label"
if [ ! -f "$dir/ca.pem" ] || [ ! -f "$dir/ca.key" ]; then
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days "$days" \
    -subj /CN=tessera-ca -keyout "$dir/ca.key" -out "$dir/ca.pem" 2>/dev/null
  chmod 0644 "$dir/ca.pem"
  echo "made the CA: $dir/ca.pem (keep $dir/ca.key off the workers)"
fi
if [ ! -s "$dir/tessera.token" ]; then
  openssl rand -hex 32 >"$dir/tessera.token"
  echo "made the token: $dir/tessera.token"
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
openssl req -new -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -subj "/CN=$1" \
  -keyout "$dir/$label/worker.key" -out "$work/worker.csr" 2>/dev/null
printf 'subjectAltName=%s\n' "$sans" >"$work/worker.ext"
openssl x509 -req -in "$work/worker.csr" -CA "$dir/ca.pem" -CAkey "$dir/ca.key" \
  -CAserial "$work/ca.srl" -CAcreateserial -days "$days" -extfile "$work/worker.ext" \
  -out "$dir/$label/worker.pem" 2>/dev/null
chmod 0644 "$dir/$label/worker.pem"
echo "made a worker certificate for $sans: $dir/$label/worker.pem, $dir/$label/worker.key"
