package main

import (
	"fmt"
	"os"
	"strings"
	"unicode"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	lbsolidv1 "lbsolid/v1"
)

// Exit codes, the same as the lbsolid CLI's.
const (
	exitDone      = 0 // the session reached DONE
	exitRunFailed = 1 // the session FAILED or was CANCELLED
	exitBadInput  = 2 // usage, scenario, or a request the daemon refuses for good
	exitTransient = 3 // unreachable daemon or a transient error: retrying may help
)

func fail(code int, format string, args ...interface{}) int {
	fmt.Fprintf(os.Stderr, "lbsolid-go-profiles: "+format+"\n", args...)
	return code
}

// rpcFailure reports a failed call with its gRPC status code and message.
func rpcFailure(call string, err error) int {
	s := status.Convert(err)
	exit := exitTransient
	switch s.Code() {
	case codes.InvalidArgument, codes.NotFound, codes.AlreadyExists, codes.FailedPrecondition,
		codes.DataLoss, codes.OutOfRange, codes.Unimplemented, codes.PermissionDenied, codes.Unauthenticated:
		exit = exitBadInput
	}
	return fail(exit, "%s failed: %s: %s", call, codeName(s.Code()), s.Message())
}

// codeName spells a status code as gRPC's documentation does: INVALID_ARGUMENT, not InvalidArgument.
func codeName(c codes.Code) string {
	name := c.String()
	if name == "OK" || strings.HasPrefix(name, "Code(") {
		return name
	}
	var b strings.Builder
	for i, r := range name {
		if i > 0 && unicode.IsUpper(r) {
			b.WriteByte('_')
		}
		b.WriteRune(unicode.ToUpper(r))
	}
	return b.String()
}

// reportEnd says how the session ended and returns the exit code.
func reportEnd(session *lbsolidv1.Session, frames int) int {
	state := session.GetState()
	switch state {
	case lbsolidv1.SessionState_SESSION_STATE_DONE:
		fmt.Fprintf(os.Stderr, "session %s DONE at step %d, %d frames\n", session.GetId(), session.GetStep(), frames)
		return exitDone
	case lbsolidv1.SessionState_SESSION_STATE_FAILED:
		return fail(exitRunFailed, "session %s FAILED: %s", session.GetId(), session.GetMessage())
	case lbsolidv1.SessionState_SESSION_STATE_CANCELLED:
		return fail(exitRunFailed, "session %s was CANCELLED at step %d", session.GetId(), session.GetStep())
	default:
		return fail(exitTransient, "the profile stream ended but session %s is %s at step %d", session.GetId(), state, session.GetStep())
	}
}
