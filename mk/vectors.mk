# A new software version, the maintainer's way (docs/adding-a-firmware.md): start its golden
# vectors from the newest of its series, then run every golden vector through every target.

.PHONY: new-vector

## new-vector: start VERSION's robot-state vectors from the newest of its series, values marked
## `TODO: check` for a person to lay out (make new-vector VERSION=5.27 [VECTOR=tests/golden/...])
new-vector:
	@test -n "$(VERSION)" || { echo "usage: make new-vector VERSION=5.27 [VECTOR=tests/golden/<file>]" >&2; exit 2; }
	$(PYTHON) scripts/new_vector.py $(VERSION) $(if $(VECTOR),--from $(VECTOR))
