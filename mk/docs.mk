# The pictures of docs/ that the build draws (docs/img/). dissector/README.md's Wireshark pictures
# are lua.mk's `make screenshots`.

.PHONY: docs-pictures

## docs-pictures: docs/img/recording-view.png from scratch: `urwire serve` recorded by `urwire listen
## --mcap` for 20 s, then drawn from the MCAP file by `urwire plot` (docs/recording-view.md; needs
## urwire[mcap,plot])
docs-pictures:
	bash scripts/recording-view.sh
