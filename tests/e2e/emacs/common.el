;;; common.el --- What the Emacs end-to-end tests share  -*- lexical-binding: t; -*-

;; The Emacs tests run `emacs --batch -q' (tests/e2e/run), with HOME a scratch
;; folder and `gloc' (target/debug/gloc) first on PATH, as a user's installed
;; binary would be. Environment: GLOC_SETUP, the guide's setup block for the
;; client under test (docs/editors.md, word for word but for /path/to/gloc);
;; GLOC_REPO, the repository.

(require 'cl-lib)

(defvar gloc-test-failures 0)

(defun gloc-test-check (ok what &optional detail)
  "Report WHAT as passed when OK, else as failed with DETAIL."
  (if ok
      (princ (format "ok: %s\n" what))
    (setq gloc-test-failures (1+ gloc-test-failures))
    (princ (format "FAILED: %s%s\n" what (if detail (format " (%S)" detail) "")))))

(defun gloc-test-finish ()
  "Exit 0 when every check passed, 1 otherwise."
  (princ (format "%s\n" (if (zerop gloc-test-failures) "all passed"
                           (format "%d failed" gloc-test-failures))))
  (kill-emacs (if (zerop gloc-test-failures) 0 1)))

(defun gloc-test-wait (predicate &optional seconds)
  "Process events until PREDICATE holds or SECONDS (default 20) pass; its value."
  (let ((deadline (+ (float-time) (or seconds 20)))
        value)
    (while (and (not (setq value (funcall predicate)))
                (< (float-time) deadline))
      (accept-process-output nil 0.05)
      (sit-for 0))
    value))

(defvar gloc-test-repo (file-name-as-directory (getenv "GLOC_REPO")))

(defun gloc-test-project ()
  "A scratch project: Fig. 2 as GLOC, Fig. 3 as GBASIC, comet's nsb3.mi with its
.ma files; returns its folder."
  (let ((root (file-name-as-directory (make-temp-file "gloc-emacs-" t))))
    (make-directory (expand-file-name "missions" root))
    (copy-file (expand-file-name "examples/fig2.gloc" gloc-test-repo)
               (expand-file-name "fig2.gloc" root))
    (copy-file (expand-file-name "examples/fig3.gbas" gloc-test-repo)
               (expand-file-name "fig3.gbas" root))
    (copy-file (expand-file-name "data/comet/missions/nsb3.mi" gloc-test-repo)
               (expand-file-name "missions/nsb3.mi" root))
    (copy-directory (expand-file-name "data/comet/mafiles" gloc-test-repo)
                    (expand-file-name "mafiles" root) nil t t)
    root))

(defun gloc-test-type-line (after-line text)
  "Open a line after line AFTER-LINE (1-based; 0: at the end), insert TEXT, leave point at its end."
  (goto-char (point-min))
  (if (zerop after-line)
      (progn (goto-char (point-max))
             (unless (bolp) (insert "\n")))
    (forward-line after-line))
  (insert text "\n")
  (forward-line -1)
  (end-of-line))

(defun gloc-test-choose (capf candidate)
  "Complete at point with the completion data CAPF, choosing CANDIDATE as a
completion UI does: replace the typed text with it, then run the exit function.
Returns the candidates the table offered for the typed text."
  (cl-destructuring-bind (start end table &rest props) capf
    (let* ((typed (buffer-substring-no-properties start end))
           (all (all-completions typed table))
           (chosen (car (member candidate all)))
           (exit (plist-get props :exit-function)))
      (when chosen
        (delete-region start end)
        (goto-char start)
        (insert chosen)
        (when exit (funcall exit chosen 'finished)))
      (mapcar #'substring-no-properties all))))

(defun gloc-test-line ()
  "The current line's text."
  (buffer-substring-no-properties (line-beginning-position) (line-end-position)))

(provide 'common)
;;; common.el ends here
