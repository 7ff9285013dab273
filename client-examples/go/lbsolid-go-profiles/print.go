package main

import (
	"bufio"
	"fmt"
	"io"
	"strconv"

	lbsolidv1 "lbsolid/v1"
)

// framePrinter writes profile frames to stdout: a readable table per frame, or with --print-hex one
// exact line per frame, "profile STEP NY y[NY] u_x[NY]", each number a hexadecimal float
// (strconv 'x' format, e.g. 0x1.8p+01; the same value as C's %a 0x1.8p+1).
type framePrinter struct {
	out *bufio.Writer
	hex bool
}

func newFramePrinter(w io.Writer, hex bool) *framePrinter {
	return &framePrinter{out: bufio.NewWriter(w), hex: hex}
}

func (p *framePrinter) print(frame *lbsolidv1.ProfileFrame) error {
	y, u := frame.GetY(), frame.GetUX()
	if len(y) != len(u) {
		return fmt.Errorf("frame at step %d has %d y values but %d u_x values", frame.GetStep(), len(y), len(u))
	}
	if p.hex {
		fmt.Fprintf(p.out, "profile %d %d", frame.GetStep(), len(y))
		for _, values := range [][]float64{y, u} {
			for _, v := range values {
				p.out.WriteByte(' ')
				p.out.WriteString(strconv.FormatFloat(v, 'x', -1, 64))
			}
		}
		p.out.WriteByte('\n')
	} else {
		fmt.Fprintf(p.out, "step %d (%d rows", frame.GetStep(), len(y))
		if s := frame.GetSkippedFrames(); s > 0 {
			fmt.Fprintf(p.out, ", %d frames skipped so far", s)
		}
		fmt.Fprintf(p.out, ")\n%12s  %14s\n", "y", "u_x")
		for j := range y {
			fmt.Fprintf(p.out, "%12.6f  %14.6e\n", y[j], u[j])
		}
		p.out.WriteByte('\n')
	}
	return p.out.Flush() // a frame at a time, so a watcher of a long run sees it at once
}

func (p *framePrinter) flush() error { return p.out.Flush() }
