#!/bin/sh
# Make a usrpwd dictionary for router-usrpwd.json5 / router-acl.json5, with random passwords.
#
#   ./make-users.sh [FILE [USER...]]
#
# FILE defaults to ./users.txt; the default users are the zenros services plus a read-only
# "viewer". One "user:password" line per user, file mode 600. Refuses to overwrite FILE unless
# FORCE=1. Give each process its own password in a private copy of client-usrpwd.json5.
# Never commit the output: deploy/zenoh/.gitignore excludes users.txt.
set -eu

file=${1:-./users.txt}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] || set -- gateway nav chassis tf master tasks viewer

if [ -e "$file" ] && [ "${FORCE:-0}" != 1 ]; then
    echo "make-users.sh: $file exists; set FORCE=1 to replace it" >&2
    exit 1
fi
umask 077
tmp="$file.tmp.$$"
trap 'rm -f "$tmp"' EXIT
: > "$tmp"
for user in "$@"; do
    case $user in
        *:* | "") echo "make-users.sh: invalid user name '$user' (no ':' allowed)" >&2; exit 1 ;;
    esac
    pw=$(head -c 18 /dev/urandom | od -An -tx1 | tr -d ' \n')
    printf '%s:%s\n' "$user" "$pw" >> "$tmp"
done
mv "$tmp" "$file"
trap - EXIT
echo "wrote $# users to $file (mode 600): $*"
