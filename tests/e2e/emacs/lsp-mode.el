;;; lsp-mode.el --- Emacs with lsp-mode, set up as docs/editors.md says  -*- lexical-binding: t; -*-

;; Run by tests/e2e/run: emacs --batch -q -l tests/e2e/emacs/lsp-mode.el, with
;; GLOC_SETUP the guide's `emacs-lsp-mode' block. Opens Fig. 2 as GLOC, Fig. 3
;; as GBASIC and comet's nsb3.mi, and completes in each: `loads m_dep' →
;; `loads m_depth', `m_dep' → `m_depth', `b_arg: d_t' → `b_arg: d_target_depth(m) 12'.

(load (expand-file-name "common.el" (file-name-directory load-file-name)) nil t)

;; What a normal start does and batch mode skips: activate the installed packages.
(package-initialize)
(defvar gloc-root (gloc-test-project))
;; The answer a user gives to lsp-mode's first question ("import project root?"),
;; which batch mode cannot ask: the scratch project is a known workspace folder.
(setq lsp-session-file (expand-file-name "lsp-session" gloc-root))
(load (getenv "GLOC_SETUP") nil t)
(lsp-workspace-folders-add gloc-root)

(defun gloc-open (file)
  "Visit FILE of the project as a user does; lsp-mode starts from the mode hook."
  (find-file (expand-file-name file gloc-root))
  (gloc-test-wait (lambda () (and (bound-and-true-p lsp-mode) (lsp-workspaces)
                                  (eq (lsp--workspace-status (car (lsp-workspaces))) 'initialized))))
  (gloc-test-check (and (bound-and-true-p lsp-mode) (lsp-workspaces))
                   (format "lsp-mode manages %s" file) major-mode))

(defun gloc-errors (&optional seconds)
  "This buffer's errors from the server after SECONDS (default 2)."
  (gloc-test-wait (lambda () nil) (or seconds 2))
  (let ((this (file-truename buffer-file-name))
        errors)
    (maphash (lambda (file diagnostics)
               (when (equal (file-truename file) this)
                 (dolist (diagnostic diagnostics)
                   (when (eq (lsp:diagnostic-severity? diagnostic) 1)
                     (push (lsp:diagnostic-message diagnostic) errors)))))
             (lsp-diagnostics t))
    errors))

(defun gloc-complete-and-choose (candidate)
  "Ask for completion at point and choose CANDIDATE; the candidates offered."
  (gloc-test-choose (lsp-completion-at-point) candidate))

(gloc-open "fig2.gloc")
(gloc-test-check (eq major-mode 'gloc-mode) "fig2.gloc is in gloc-mode" major-mode)
(let ((errors (gloc-errors)))
  (gloc-test-check (null errors) "Fig. 2 has no errors" errors))
(gloc-test-type-line 0 "loads m_dep")
(let ((offered (gloc-complete-and-choose "m_depth")))
  (gloc-test-check (member "m_depth" offered) "`loads m_dep' offers m_depth by name"
                   (seq-take offered 10))
  (gloc-test-check (equal (gloc-test-line) "loads m_depth") "choosing it inserts the name: `loads m_depth'"
                   (gloc-test-line)))
(set-buffer-modified-p nil)

(gloc-open "fig3.gbas")
(gloc-test-check (eq major-mode 'gbasic-mode) "fig3.gbas is in gbasic-mode" major-mode)
(gloc-test-type-line 0 "x = m_dep")
(let ((offered (gloc-complete-and-choose "m_depth")))
  (gloc-test-check (member "m_depth" offered) "`m_dep' offers m_depth in GBASIC" (seq-take offered 10))
  (gloc-test-check (equal (gloc-test-line) "x = m_depth") "choosing it gives `x = m_depth'"
                   (gloc-test-line)))
(set-buffer-modified-p nil)

(gloc-open "missions/nsb3.mi")
(gloc-test-check (eq major-mode 'slocum-mission-mode) "nsb3.mi is in slocum-mission-mode" major-mode)
(let ((errors (gloc-errors)))
  (gloc-test-check (null errors) "nsb3.mi has no errors" errors))
;; Line 67 is yo's `args_from_file' line; a new argument of yo under it.
(gloc-test-type-line 67 "    b_arg: d_t")
(let ((offered (gloc-complete-and-choose "d_target_depth")))
  (gloc-test-check (member "d_target_depth" offered) "`b_arg: d_t' offers d_target_depth" offered)
  ;; lsp-mode 8.0 declares snippets only with yasnippet loaded: the default comes filled in.
  (gloc-test-check (equal (gloc-test-line) "    b_arg: d_target_depth(m) 12")
                   "choosing it inserts `d_target_depth(m) 12'" (gloc-test-line)))
(set-buffer-modified-p nil)

(lsp-workspace-shutdown (car (lsp-workspaces)))
(gloc-test-finish)
