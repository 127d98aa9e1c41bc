#!/bin/sh
# Make a throw-away TLS test PKI for the zenros Zenoh configs (router-tls, router-mtls).
#
#   ./make-certs.sh [DIR]          (DIR defaults to ./certs)
#
# Writes, in DIR:
#   ca.pem / ca.key          a self-signed CA (basicConstraints CA:TRUE)
#   server.pem / server.key  CN=localhost, SAN DNS:localhost,IP:127.0.0.1, serverAuth
#   client.pem / client.key  CN=client1, clientAuth (for mTLS)
# Keys are RSA 2048 in PKCS#8 (what zenoh's rustls loader reads). Set CERT_DAYS to change the
# validity (default 365) and SERVER_SAN to add names, e.g.
#   SERVER_SAN="DNS:localhost,IP:127.0.0.1,IP:192.168.1.10" ./make-certs.sh
# Never commit the output: deploy/zenoh/.gitignore excludes certs/.
set -eu

dir=${1:-./certs}
days=${CERT_DAYS:-365}
san=${SERVER_SAN:-DNS:localhost,IP:127.0.0.1}

command -v openssl >/dev/null 2>&1 || { echo "make-certs.sh: openssl not found on PATH" >&2; exit 1; }
mkdir -p "$dir"
umask 077
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

key() { openssl genpkey -algorithm RSA -pkeyopt rsa_keygen_bits:2048 -out "$1" 2>/dev/null; }

# CA
key "$dir/ca.key"
cat > "$tmp/ca.ext" <<EXT
basicConstraints=critical,CA:TRUE
keyUsage=critical,keyCertSign,cRLSign
subjectKeyIdentifier=hash
EXT
openssl req -new -key "$dir/ca.key" -subj "/CN=zenros test CA" -out "$tmp/ca.csr"
openssl x509 -req -in "$tmp/ca.csr" -signkey "$dir/ca.key" -days "$days" \
    -extfile "$tmp/ca.ext" -out "$dir/ca.pem" 2>/dev/null

# issue NAME CN EXTFILE: a key and a certificate signed by the CA
issue() {
    key "$dir/$1.key"
    openssl req -new -key "$dir/$1.key" -subj "/CN=$2" -out "$tmp/$1.csr"
    openssl x509 -req -in "$tmp/$1.csr" -CA "$dir/ca.pem" -CAkey "$dir/ca.key" \
        -CAcreateserial -CAserial "$tmp/ca.srl" -days "$days" -extfile "$3" \
        -out "$dir/$1.pem" 2>/dev/null
}

cat > "$tmp/server.ext" <<EXT
basicConstraints=critical,CA:FALSE
keyUsage=critical,digitalSignature,keyEncipherment
extendedKeyUsage=serverAuth
subjectAltName=$san
EXT
issue server localhost "$tmp/server.ext"

cat > "$tmp/client.ext" <<EXT
basicConstraints=critical,CA:FALSE
keyUsage=critical,digitalSignature,keyEncipherment
extendedKeyUsage=clientAuth
EXT
issue client client1 "$tmp/client.ext"

chmod 644 "$dir/ca.pem" "$dir/server.pem" "$dir/client.pem"
echo "certificates written to $dir: ca.pem server.pem server.key client.pem client.key"
